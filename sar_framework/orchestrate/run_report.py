"""What ``sar-tree run`` writes and prints once its children stopped, for any robot count.

Each robot's event stream is closed with its ``verdict`` event, each robot gets the one
report (:mod:`sar_framework.report`) in its folder; named robots add the run's page
(:mod:`sar_framework.report_robots`: ``fleet.json``, ``fleet.png``) whose verdict is the
robots' (:func:`~.outcome.robots_outcome`) unless the run was cut short, and a line each.
"""

from __future__ import annotations

import functools
import json
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any, Protocol

from sar_framework.app import App
from sar_framework.events.event import EventKind, MissionEvent
from sar_framework.events.jsonl import EVENTS_FILE, EventFileWriter
from sar_framework.mission.processes import MissionSettings, Robot
from sar_framework.orchestrate.inputs import CheckedInputs
from sar_framework.orchestrate.options import RunConfig
from sar_framework.orchestrate.outcome import Outcome, cut_short, robots_outcome, where_it_ended
from sar_framework.report_robots import FLEET_JSON, FLEET_PNG


class Run(Protocol):
    """What these functions read of a run (:class:`~.orchestrator.Orchestrator`)."""

    config: RunConfig
    inputs: CheckedInputs
    spec: Any
    report_dir: Path
    robots: dict[str, Robot]
    outcomes: dict[str, Outcome]
    verdict: Outcome | None
    stop_s: float | None

    def robot_dir(self, name: str) -> Path:
        """Robot ``name``'s folder."""

    def say(self, text: str) -> None:
        """Print one line."""

ROBOT_FILES = ("status.json", EVENTS_FILE, "trace.jsonl", "mission.json", "mission.png",
               "tree.svg", "detect.log", "runner.log")
"""A named robot's files in its folder, removed before a run."""
RUN_FILES = (FLEET_JSON, FLEET_PNG)
"""The run's page of named robots, removed before a run."""


@functools.cache
def import_report_libraries() -> None:
    """Import what the report needs (numpy, Pillow, graphviz) at the runners' first event.

    Not at start-up, where it would take a core from the children starting; before the
    mission is under way, so a Ctrl-C mid-mission is not slowed by it.
    """
    import sar_framework.engine.rendering.render
    import sar_framework.report
    import sar_framework.sim.occupancy  # noqa: F401


def append_verdict(say: Callable[[str], None], events: list[MissionEvent], folder: Path,
                   outcome: Outcome, *, wall_s: float, who: str = "") -> None:
    """Append a ``verdict`` event after ``events`` to ``folder``'s events file and list.

    Args:
        say: Prints a warning when the file cannot be written.
        events: The stream so far (the verdict is appended to it once written).
        folder: Where its events file is.
        outcome: The verdict's status and reason.
        wall_s: Its wall seconds since the run started.
        who: Whose stream (a named robot), for the warning.
    """
    last = events[-1] if events else None
    verdict = MissionEvent(
        kind=EventKind.VERDICT, seq=(last.seq if last else 0) + 1,
        sim_s=last.sim_s if last else 0.0, wall_s=wall_s, status=outcome.status,
        message=outcome.reason or f"Mission {outcome.status}")
    try:
        writer = EventFileWriter(folder / EVENTS_FILE, append=True)
    except OSError as err:
        whose = f"{who}: " if who else ""
        say(f"sar-tree run: warning: {whose}could not write the verdict event: {err}")
        return
    writer(verdict)
    writer.close()
    events.append(verdict)


def robot_report(run: Run, name: str, outcome: Outcome, wall: float) -> list[Path]:
    """Robot ``name``'s mission.json, mission.png and tree.svg in its folder."""
    from sar_framework.report import MissionInputs, write_report

    robot = run.robots[name]
    inputs = MissionInputs(
        report_dir=run.robot_dir(name), tree=run.config.tree, params_file=run.config.params,
        spec=run.spec, outcome=outcome.status, reason=outcome.reason, wall_duration_s=wall,
        blocked_areas=run.inputs.blocked_areas, apps=run.inputs.apps,
        base={"x": robot.x, "y": robot.y, "yaw": robot.yaw} if name else None)
    try:
        return write_report(inputs)
    except Exception as err:  # a report problem must not hide the mission's verdict
        whose = f"{name}: " if name else ""
        run.say(f"sar-tree run: warning: {whose}could not write the report: "
                f"{type(err).__name__}: {err}")
        return []


def _summary(path: Path) -> dict[str, Any]:
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}


def robots_page(run: Run, outcome: Outcome, wall: float) -> list[Path]:
    """The run's verdict (``run.verdict``), ``fleet.json`` and ``fleet.png``."""
    from sar_framework.orchestrate.config import mission_settings

    settings = mission_settings(run.config, run.report_dir, apps=run.inputs.apps,
                                robots=run.inputs.robots, node_kinds=run.inputs.node_kinds)
    outcomes = {name: run.outcomes.get(name, outcome) for name in run.robots}
    run.verdict, written = write_robots_page(settings, run.inputs.apps, outcomes, outcome,
                                             wall_s=wall, say=run.say)
    return written


def write_robots_page(settings: MissionSettings, apps: Sequence[App],
                      outcomes: Mapping[str, Outcome], outcome: Outcome, *, wall_s: float,
                      say: Callable[[str], None]) -> tuple[Outcome, list[Path]]:
    """Named robots' verdict, ``fleet.json`` and ``fleet.png`` in the run folder.

    Args:
        settings: What the run started (its robots, run folder, node kinds).
        apps: The tree's apps.
        outcomes: Robot name -> its verdict.
        outcome: How the run ended (a cut-short run keeps its verdict).
        wall_s: Wall seconds of the whole run.
        say: Prints a warning (``fleet.png`` not drawn).

    Returns:
        The run's verdict and the files written.
    """
    from sar_framework.report_robots import (
        app_findings,
        draw_fleet,
        fleet_document,
        write_fleet_json,
    )

    folder = Path(settings.run_folder)
    summaries = {robot.name: _summary(settings.robot_folder(robot) / "mission.json")
                 for robot in settings.robots}
    keys, problems = app_findings(settings, summaries, apps)
    verdict = cut_short(outcome, robots_outcome(outcomes, problems))
    document = fleet_document(verdict.status, verdict.reason, outcomes, summaries, keys,
                              wall_duration_s=wall_s)
    written = [write_fleet_json(folder, document)]
    try:
        written.append(draw_fleet(folder, document, apps, folder / FLEET_PNG))
    except Exception as err:
        say(f"warning: could not draw {FLEET_PNG}: {type(err).__name__}: {err}")
    return verdict, written


def conclude_robots(run: Run, outcome: Outcome) -> int:
    """Print a line per named robot and the run's; return the run's exit code."""
    verdict = run.verdict or outcome
    for name in run.robots:
        summary = _summary(run.robot_dir(name) / "mission.json")
        own = run.outcomes.get(name, outcome)
        sim = summary.get("sim_duration_s") or 0.0
        run.say(f"sar-tree run: {name}: {own.status}; {sim:.1f} s simulated; "
                f"{where_it_ended(summary)}")
    run.say(f"sar-tree run: Fleet {verdict.status}"
            + (f": {verdict.reason}" if verdict.reason else ""))
    if verdict.status == "INTERRUPTED" and run.stop_s is not None:
        run.say(f"sar-tree run: every process stopped {run.stop_s:.2f} s after the signal")
    run.say(f"sar-tree run: report in {run.report_dir}/ ({FLEET_JSON}, {FLEET_PNG}; each "
            "robot's mission.json, mission.png and logs in its folder)")
    return verdict.exit_code
