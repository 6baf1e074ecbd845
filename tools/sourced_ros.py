"""Set-up on a machine with a sourced ROS 2 Jazzy (``source /opt/ros/jazzy/setup.bash``).

There the ROS install is the environment, as in any colcon workspace: the venv is made with
the interpreter ROS was built for (Ubuntu 24.04's python3.12), sees its packages through the
sourced ``PYTHONPATH`` and Debian's site-packages (``--system-site-packages``), and gets no
ROS wheels, no overlay build and no stand-ins. Of our pinned Python requirements only those
the ROS environment does not already provide are installed, so the venv never shadows a
package ROS's C extensions were built against (NumPy, PyYAML, py_trees, ...). Our own
interfaces are built against the sourced prefix into the venv, and a start-up hook puts the
venv's lib/ on ``LD_LIBRARY_PATH`` (ROS's type support loader opens a package's libraries by
name), as the ROS wheels' bootstrapper does on the other path and a workspace's
``setup.bash`` does in a ROS shell: ``.venv/bin/*`` work with nothing more sourced.
"""

from __future__ import annotations

import os
import re
import shutil
from dataclasses import dataclass
from pathlib import Path

from setup_base import SetupError, run

DISTRO = "jazzy"
# ``name==1.0  # comment`` -> ``name``; the names compare as PEP 503 normalises them.
_REQUIREMENT = re.compile(r"^\s*([A-Za-z0-9][A-Za-z0-9._-]*)")


@dataclass(frozen=True)
class SourcedRos:
    """A sourced ROS 2 Jazzy environment.

    Attributes:
        prefix: The ament prefix that provides launch_ros (e.g. ``/opt/ros/jazzy``).
        python: The interpreter that imports its rclpy (``python3`` on ``PATH``).
        version: That interpreter's ``major.minor`` (``3.12`` on Ubuntu 24.04).
    """

    prefix: str
    python: str
    version: str


def sourced_ros_prefix() -> str | None:
    """Return the sourced ROS 2 Jazzy prefix that provides launch_ros, or None."""
    if os.environ.get("ROS_DISTRO") != DISTRO:
        return None
    for prefix in filter(None, os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep)):
        if (Path(prefix) / "share" / "launch_ros" / "package.xml").exists():
            return prefix
    return None


def detect_sourced_ros() -> SourcedRos | None:
    """Return the sourced ROS 2 Jazzy, or None when none is sourced.

    Raises:
        SetupError: ROS 2 Jazzy is sourced but ``python3`` cannot import its rclpy.
    """
    prefix = sourced_ros_prefix()
    if prefix is None:
        return None
    python = shutil.which("python3")
    if python is None:
        raise SetupError(f"ROS 2 Jazzy is sourced ({prefix}) but there is no python3 on PATH")
    try:
        out = run([python, "-c", "import rclpy, sys; print('%d.%d' % sys.version_info[:2])"],
                  what=f"importing rclpy with {python}")
    except SetupError as err:
        reason = [line for line in str(err).splitlines() if line.strip()][-1:]
        raise SetupError(
            f"ROS 2 Jazzy is sourced ({prefix}) but {python} cannot import rclpy "
            f"({''.join(reason).strip()}): source {prefix}/setup.bash in this shell again, "
            "or unset ROS_DISTRO to use the PyPI wheels instead.") from None
    return SourcedRos(prefix=prefix, python=python, version=out.strip().splitlines()[-1])


def normalised(name: str) -> str:
    """A distribution name as PEP 503 compares it (``PyYAML`` -> ``pyyaml``)."""
    return re.sub(r"[-_.]+", "-", name).lower()


def provided_distributions(python: str) -> set[str]:
    """The normalised names of every distribution ``python`` sees outside any venv."""
    out = run([python, "-c", "import importlib.metadata as m\n"
               "for d in m.distributions(): print(d.metadata['Name'] or '')"],
              what="listing the Python packages of the ROS environment")
    return {normalised(line) for line in out.splitlines() if line.strip()}


def requirements_not_provided(requirements: list[Path], provided: set[str], dest: Path) -> Path:
    """Write the requirement lines whose package the ROS environment lacks into ``dest``.

    Args:
        requirements: Pinned requirement files.
        provided: Normalised names already importable (see :func:`provided_distributions`).
        dest: The file to write.

    Returns:
        ``dest``.
    """
    kept = []
    for req in requirements:
        for line in req.read_text().splitlines():
            match = _REQUIREMENT.match(line.split("#", 1)[0])
            if match and normalised(match.group(1)) not in provided:
                kept.append(line)
    dest.parent.mkdir(parents=True, exist_ok=True)
    dest.write_text("".join(f"{line}\n" for line in kept))
    return dest


def interface_build_env(venv: Path, sourced: SourcedRos | None) -> dict[str, str]:
    """The environment to build an interface package into ``venv`` with.

    Args:
        venv: The venv (its prefix is the install prefix).
        sourced: The sourced ROS (whose prefixes are searched after the venv), or None.
    """
    env = dict(os.environ)
    env["PATH"] = f"{venv / 'bin'}{os.pathsep}{env.get('PATH', '')}"
    prefixes = [str(venv)]
    if sourced is not None:
        for variable in ("CMAKE_PREFIX_PATH", "AMENT_PREFIX_PATH"):
            prefixes += [p for p in env.get(variable, "").split(os.pathsep) if p]
    env["CMAKE_PREFIX_PATH"] = os.pathsep.join(dict.fromkeys(prefixes))
    env["AMENT_PREFIX_PATH"] = env["CMAKE_PREFIX_PATH"]
    return env


LIBRARY_PATH_HOOK = "sar_library_path"
_HOOK_SOURCE = '''"""Re-run this interpreter once with the venv's lib/ on LD_LIBRARY_PATH.

Written by sar_framework's tools/bootstrap.py into a venv made over a sourced ROS 2: ROS's
type support loader opens our interface libraries by name, from the library path only.
"""
import os
import sys

_lib = os.path.join(sys.prefix, "lib")
_parts = [p for p in os.environ.get("LD_LIBRARY_PATH", "").split(os.pathsep) if p]
if _lib not in _parts and not os.environ.get("SAR_LIBRARY_PATH_SET"):
    os.environ["LD_LIBRARY_PATH"] = os.pathsep.join([_lib, *_parts])
    os.environ["SAR_LIBRARY_PATH_SET"] = "1"  # never loop, whatever happens to the path
    try:
        os.execv(sys.executable, sys.orig_argv)
    except OSError:
        pass  # carry on without: only our own message types would fail to load
'''


def install_library_path_hook(venv: Path) -> None:
    """Put the venv's lib/ on ``LD_LIBRARY_PATH`` of every interpreter the venv starts."""
    site = next((venv / "lib").glob("python3*/site-packages"))
    module = site / f"{LIBRARY_PATH_HOOK}.py"
    if not module.exists() or module.read_text() != _HOOK_SOURCE:
        module.write_text(_HOOK_SOURCE)
    (site / f"{LIBRARY_PATH_HOOK}.pth").write_text(f"import {LIBRARY_PATH_HOOK}\n")
