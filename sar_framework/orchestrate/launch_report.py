"""The report of a mission started by ``ros2 launch``: the same files as ``sar-tree run``'s.

When the launch's runner exits, :func:`write_launch_report` writes ``mission.json``,
``mission.png`` and ``tree.svg`` into the run's folder (where the runner's status and
events, and the simulator's trace, already are), from the runner's exit code, as
``sar-tree run`` does (:func:`~sar_framework.orchestrate.outcome.runner_exit_outcome`).
Named robots (``robots:=N``, ``fleet_file:=FILE``): once every runner has exited,
:func:`write_robots_launch_report` writes each robot's report into its folder and the run's
``fleet.json`` and ``fleet.png`` (:func:`~.run_report.write_robots_page`).
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from sar_framework.app import App
from sar_framework.events.jsonl import EVENTS_FILE, read_events
from sar_framework.mission.processes import MissionSettings, Robot
from sar_framework.orchestrate.outcome import Outcome, read_status, runner_exit_outcome
from sar_framework.orchestrate.run_report import write_robots_page


def _robot_report(settings: MissionSettings, apps: list[App], robot: Robot, exit_code: int,
                  *, spec: Any, wall_s: float) -> tuple[Outcome, list[Path]]:
    """One robot's verdict and report, in its folder."""
    from sar_framework.report import MissionInputs, write_report

    folder = settings.robot_folder(robot)
    outcome = runner_exit_outcome(exit_code, read_events(folder / EVENTS_FILE),
                                  read_status(folder), "see the runner's log")
    return outcome, write_report(MissionInputs(
        report_dir=folder, tree=settings.tree, params_file=settings.params_file, spec=spec,
        outcome=outcome.status, reason=outcome.reason, wall_duration_s=wall_s, apps=apps,
        base={"x": robot.x, "y": robot.y, "yaw": robot.yaw} if robot.name else None))


def _spec(settings: MissionSettings) -> Any:
    from sar_framework.engine.api import validate

    return validate(settings.tree, plugin_paths=settings.plugin_paths).spec


def write_launch_report(settings: MissionSettings, apps: list[App], exit_code: int,
                        started: float) -> list[Path]:
    """Write the run's report into its folder; return the files written.

    Args:
        settings: What the launch started (its run folder is the status file's).
        apps: The tree's apps (their parts of the report).
        exit_code: The runner's exit code.
        started: ``time.monotonic()`` when the launch described the mission.
    """
    return _robot_report(settings, apps, settings.robots[0], exit_code, spec=_spec(settings),
                         wall_s=time.monotonic() - started)[1]


def write_robots_launch_report(settings: MissionSettings, apps: list[App],
                               exit_codes: Mapping[str, int], started: float
                               ) -> tuple[Outcome, list[Path]]:
    """Write each named robot's report and the run's page; return the verdict and files.

    Args:
        settings: What the launch started (its robots).
        apps: The tree's apps.
        exit_codes: Robot name -> its runner's exit code.
        started: ``time.monotonic()`` when the launch described the mission.
    """
    spec, wall = _spec(settings), time.monotonic() - started
    outcomes: dict[str, Outcome] = {}
    written: list[Path] = []
    for robot in settings.robots:
        outcomes[robot.name], files = _robot_report(
            settings, apps, robot, exit_codes.get(robot.name, 1), spec=spec, wall_s=wall)
        written += files
    verdict, page = write_robots_page(settings, apps, outcomes, Outcome("SUCCESS", 0),
                                      wall_s=wall, say=lambda _text: None)
    return verdict, written + page
