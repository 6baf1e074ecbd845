"""The embedded simulator and the installed apps' processes as child processes, for tests.

::

    with MissionStack(tmp_path) as stack:      # waits until each one logs "ready"
        ...                                     # navigate_to_pose, the apps' services, ...
    stack.output("sim")                         # what the simulator has logged

They run on the ROS environment of the calling process (a private domain with
:func:`~sar_framework.testing.ros_env.lease_domain_id`, as the ``sar_ros_domain``
fixture sets it). The simulator runs on simulated time (``speed`` simulated seconds per
wall second) and the servers follow it (``use_sim_time``).

Their command lines come from :mod:`sar_framework.mission.processes`, the one description
of the mission's processes that ``sar-tree run`` and the launch file start from too: the
stack is that mission without its runner, with the processes of every installed app.
"""

from __future__ import annotations

from pathlib import Path
from types import TracebackType
from typing import Any

from sar_framework.app import discover_apps
from sar_framework.mission.processes import MissionSettings, mission_processes, ros_arguments
from sar_framework.testing.processes import NodeProcess

READY_S = 30.0  # start-up on a loaded 2-core machine: imports and discovery


class MissionStack:
    """The simulator and the installed apps' processes.

    Args:
        log_dir: The run's folder: each process's log (``sim.log``, ``LABEL.log`` per app
            process) and the files the apps' processes write there.
        speed: Simulated seconds per wall second (None: the simulator's own default).
        app_params: Parameters of the apps' processes by label, as ``sar-tree run
            --LABEL-param NAME:=VALUE`` sets them (e.g. a file an app's server reads).
    """

    def __init__(self, log_dir: Path, *, speed: float | None = None,
                 app_params: dict[str, dict[str, Any]] | None = None) -> None:
        self.log_dir = Path(log_dir)
        self.log_dir.mkdir(parents=True, exist_ok=True)
        settings = MissionSettings(tree="", params_file="", speed=speed,
                                   run_folder=str(self.log_dir), extra=dict(app_params or {}))
        self.processes = [
            NodeProcess(["-m", process.module, "--ros-args", *ros_arguments(process)],
                        process.label, log_dir=self.log_dir)
            for process in mission_processes(settings, discover_apps())
            if process.label != "runner"]

    def start(self) -> MissionStack:
        """Start them all and wait until each has logged ``ready``."""
        for process in self.processes:
            process.start()
        try:
            for process in self.processes:
                process.wait_for_output(r"\bready\b", timeout=READY_S)
        except BaseException:
            self.stop()
            raise
        return self

    def stop(self) -> None:
        """Stop the apps' processes, then the simulator (SIGINT, then SIGKILL)."""
        for process in reversed(self.processes):
            if process.started:
                process.stop()

    def output(self, label: str) -> str:
        """What the process labelled ``label`` (``sim``, an app's) has logged so far."""
        return next(p for p in self.processes if p.label == label).output

    def __enter__(self) -> MissionStack:
        return self.start()

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        self.stop()
