"""What the launch files share: file arguments found in the package share, processes as Nodes.

``launch/tree.launch.py`` (which ``launch/search_and_rescue.launch.py`` and, through it,
``launch/fleet.launch.py`` include) turns the process descriptions of
:mod:`sar_framework.mission.processes` into ``launch_ros`` ``Node`` actions here, so a
process described once starts the same way from a launch and from ``sar-tree run``.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

PACKAGE = "sar_framework"


def package_file(text: str, folder: str = "") -> str:
    """Resolve a file argument: as given if it exists, else inside the package share.

    Args:
        text: The argument's value.
        folder: A share sub-folder to try a bare name in (e.g. ``trees``).

    Returns:
        An absolute path (the share's, even when missing, so the error names it).
    """
    from ament_index_python.packages import get_package_share_directory

    given = Path(text).expanduser()
    if given.is_absolute() or given.exists():
        return str(given.resolve())
    share = Path(get_package_share_directory(PACKAGE))
    candidates = [share / given]
    if folder:
        candidates += [share / folder / given, share / folder / f"{given}.yaml"]
    return str(next((c for c in candidates if c.is_file()), candidates[0]))


def launch_parameters(parameters: dict[str, Any]) -> dict[str, Any]:
    """The parameters with their types kept: launch_ros reads a bare string as YAML."""
    from launch_ros.parameter_descriptions import ParameterValue

    typed: dict[str, Any] = {}
    for name, value in parameters.items():
        if isinstance(value, str):
            typed[name] = ParameterValue(value, value_type=str)
        elif isinstance(value, list) and value and all(isinstance(v, str) for v in value):
            typed[name] = ParameterValue(value, value_type=list[str])
        else:
            typed[name] = value
    return typed


def process_node(process: Any) -> Any:
    """A process description as a launch action: its executable, namespace, parameters.

    A program of this package is a ``launch_ros`` Node; an app's own program, which this
    package does not install (no :attr:`~sar_framework.mission.processes.Process.executable`),
    runs as ``python -m MODULE --ros-args ...``, as ``sar-tree run`` starts it, with its
    ``python_path`` before ``PYTHONPATH``.

    Args:
        process: A :class:`~sar_framework.mission.processes.Process`.
    """
    if not process.executable:
        import os

        from launch.actions import ExecuteProcess

        from sar_framework.mission.processes import ros_arguments

        path = [*process.python_path, *filter(None, [os.environ.get("PYTHONPATH", "")])]
        return ExecuteProcess(
            cmd=[sys.executable, "-m", process.module, "--ros-args", *ros_arguments(process)],
            name=process.name, additional_env={"PYTHONPATH": os.pathsep.join(path)},
            output="screen", emulate_tty=sys.stdout.isatty())
    from launch_ros.actions import Node

    return Node(package=PACKAGE, executable=process.executable,
                namespace=process.namespace or None,
                parameters=[*process.params_files, launch_parameters(process.parameters)],
                output="screen", emulate_tty=sys.stdout.isatty())
