"""The embedded simulator and the detect/report servers as child processes, for tests.

::

    with MissionStack(tmp_path) as stack:      # waits until each one logs "ready"
        ...                                     # navigate_to_pose, /detect_survivor, ...
    stack.reports()                             # what the report server recorded

They run on the ROS environment of the calling process (a private domain with
:func:`~sar_framework.testing.ros_env.lease_domain_id`, as the ``sar_ros_domain``
fixture sets it). The simulator runs on simulated time (``speed`` simulated seconds per
wall second) and the servers follow it (``use_sim_time``).

Their command lines come from :mod:`sar_framework.mission.processes`, the one description
of the mission's processes that ``sar-tree run`` and the launch file start from too: the
stack is that mission without its runner, with the processes of every installed app (the
search-and-rescue app's servers).
"""

from __future__ import annotations

import json
from pathlib import Path
from types import TracebackType
from typing import Any

from sar_framework.app import discover_apps
from sar_framework.mission.processes import MissionSettings, mission_processes, ros_arguments
from sar_framework.testing.processes import NodeProcess

READY_S = 30.0  # start-up on a loaded 2-core machine: imports and discovery


class MissionStack:
    """The simulator, the detect server and the report server.

    Args:
        log_dir: Where each process's log (``sim.log``, ``detect.log``, ``report.log``) and
            the report server's ``reports.jsonl`` go.
        speed: Simulated seconds per wall second (None: the simulator's own default).
        survivors: A survivors file for the detect server (default: its built-in table).
    """

    def __init__(self, log_dir: Path, *, speed: float | None = None,
                 survivors: Path | None = None) -> None:
        self.log_dir = Path(log_dir)
        self.log_dir.mkdir(parents=True, exist_ok=True)
        self.report_file = self.log_dir / "reports.jsonl"
        settings = MissionSettings(tree="", params_file="", speed=speed,
                                   extra={"detect": {"survivors_file": str(survivors)}
                                          if survivors else {},
                                          "report": {"report_file": str(self.report_file)}})
        self.processes = [
            NodeProcess(["-m", process.module, "--ros-args", *ros_arguments(process)],
                        process.label, log_dir=self.log_dir)
            for process in mission_processes(settings, discover_apps())
            if process.label != "runner"]

    def start(self) -> MissionStack:
        """Start all three and wait until each has logged ``ready``."""
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
        """Stop the servers, then the simulator (SIGINT, then SIGKILL)."""
        for process in reversed(self.processes):
            if process.started:
                process.stop()

    def output(self, label: str) -> str:
        """What the process ``sim``, ``detect`` or ``report`` has logged so far."""
        return next(p for p in self.processes if p.label == label).output

    def reports(self) -> list[dict[str, Any]]:
        """The survivors the report server has recorded."""
        if not self.report_file.exists():
            return []
        lines = self.report_file.read_text().splitlines()
        return [json.loads(line) for line in lines if line.strip()]

    def __enter__(self) -> MissionStack:
        return self.start()

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        self.stop()
