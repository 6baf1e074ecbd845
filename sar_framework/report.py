"""The mission report: ``mission.json``, ``mission.png`` and ``tree.svg`` in the report folder.

Plain Python (no ROS), for any tree. It reads what the mission's processes left in the
report folder:

- ``events.jsonl``: the runner's events (:mod:`sar_framework.events`): navigation goals
  sent, reached or failed (with their poses), failures and their reasons, reloads;
- ``status.json``: the runner's status file (docs/reference/mission-contracts.md): node statuses,
  ticks, clock readings, the final blackboard entry values (copied as ``entries``);
- ``trace.jsonl``: the simulator's trace (robot poses, goal events, path length), if any.

Every simulated time counts from one origin, the first tick (``sim_start_s``). Each app the
tree uses adds its own keys (:attr:`sar_framework.app.App.report`). ``mission.png`` draws
the occupancy map, the goals, blocked areas and the robot's path, and what the apps' keys show
(:mod:`sar_framework.report_map`). ``tree.svg`` is the tree coloured by each node's last
status (:func:`sar_framework.engine.rendering.render.render_to_file`).
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

from sar_framework.app import App
from sar_framework.events.event import REASON_KINDS, EventKind, MissionEvent, kind_name
from sar_framework.events.jsonl import EVENTS_FILE, read_events, read_json_lines
from sar_framework.report_map import draw_map

AT_GOAL_M = 0.5
"""A robot ending this close to its last navigation goal (metres) is at it."""


@dataclass(frozen=True)
class MissionInputs:
    """Where the report's data is.

    Attributes:
        report_dir: The report folder (inputs are read from it, outputs written to it).
        tree: The tree file, as given.
        params_file: The mission parameter file.
        spec: The tree's ``TreeSpec`` (for ``tree.svg``), or None to skip the diagram.
        outcome: ``SUCCESS``, ``FAILURE``, ``TIMEOUT``, ``INTERRUPTED`` or ``ERROR``.
        reason: Why it did not succeed ("" on success).
        wall_duration_s: Wall seconds of the whole run, set-up included.
        map_yaml: The map to draw on; None: the one the simulator ran on (its trace), else
            the simulator's default map.
        blocked_areas: Injected obstacles as ``(x, y, radius)`` metres, drawn on the map.
        base: ``{x, y, yaw}`` of this robot's base over the parameter file's (a fleet's
            robot goes home to its own spawn place).
        apps: The apps whose parts the report adds; None: every installed app, each
            adding only what the run's files show of it (a replay, a test).
    """

    report_dir: Path
    tree: str
    params_file: str
    spec: Any
    outcome: str
    reason: str = ""
    wall_duration_s: float = 0.0
    map_yaml: Path | None = None
    blocked_areas: tuple[tuple[float, float, float], ...] = ()
    base: dict[str, float] | None = None
    apps: Sequence[App] | None = None


# -- reading ------------------------------------------------------------------------------
def _read_json(path: Path) -> dict[str, Any]:
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
    return data if isinstance(data, dict) else {}


def _merge(target: dict[str, Any], source: dict[str, Any]) -> None:
    for key, value in source.items():
        if isinstance(value, dict) and isinstance(target.get(key), dict):
            _merge(target[key], value)
        else:
            target[key] = value


def read_ros_parameters(params_file: str | Path) -> dict[str, Any]:
    """Every section's ``ros__parameters`` of a ROS 2 parameter file, merged (nested).

    Args:
        params_file: The file.

    Returns:
        The values ({} when the file cannot be read; the runner has already validated it).
    """
    try:
        doc = yaml.safe_load(Path(params_file).read_text(encoding="utf-8"))
    except (OSError, yaml.YAMLError):
        return {}
    params: dict[str, Any] = {}
    for section in (doc or {}).values() if isinstance(doc, dict) else ():
        if isinstance(section, dict) and isinstance(section.get("ros__parameters"), dict):
            _merge(params, section["ros__parameters"])
    return params


def numbers(pose: Any) -> dict[str, float]:
    """The numeric entries of a pose mapping (a bad value is left out, never an error)."""
    if not isinstance(pose, dict):
        return {}
    return {k: float(v) for k, v in pose.items()
            if isinstance(v, (int, float)) and not isinstance(v, bool)}


def _final_position(trace: Sequence[dict[str, Any]]) -> dict[str, float] | None:
    """The robot's last traced position, or None."""
    poses = [r for r in trace if "x" in r and "y" in r and r.get("event") in (None, "start")]
    if not poses:
        return None
    return {"x": round(float(poses[-1]["x"]), 3), "y": round(float(poses[-1]["y"]), 3)}


def _last_goal(trace: Sequence[dict[str, Any]], final: dict[str, float] | None
               ) -> tuple[dict[str, float] | None, bool | None]:
    """Where the last navigation goal sent the robot, and whether it is within reach of it."""
    goals = [r for r in trace if r.get("event") == "accepted" and "x" in r and "y" in r]
    if not goals:
        return None, None
    x, y = float(goals[-1]["x"]), float(goals[-1]["y"])
    at_goal = (math.hypot(x - final["x"], y - final["y"]) <= AT_GOAL_M
               if final is not None else None)
    return {"x": round(x, 3), "y": round(y, 3)}, at_goal


def since_start(sim_s: float, origin: Any) -> float:
    """A ROS time as the report counts it: seconds since the first tick (``origin``).

    Args:
        sim_s: An event's ROS time, seconds.
        origin: ``sim_start_s``, the ROS time of the first tick (None when unknown: the
            time is kept as it is).
    """
    if isinstance(origin, (int, float)) and not isinstance(origin, bool):
        return round(sim_s - origin, 3)
    return sim_s


def _goals(events: Sequence[MissionEvent], origin: Any) -> list[dict[str, Any]]:
    """Every navigation goal the tree sent: where, by which node, and how it ended."""
    goals: list[dict[str, Any]] = []
    open_goals: dict[str, dict[str, Any]] = {}  # node uid -> its goal in flight
    for event in events:
        if event.position is None:
            continue
        x, y = round(event.position[0], 3), round(event.position[1], 3)
        if event.kind == EventKind.NAVIGATION:
            goal = {"node": event.node_name, "uid": event.node_uid, "kind": event.node_kind,
                    "x": x, "y": y, "sent_sim_s": since_start(event.sim_s, origin),
                    "result": None, "ended_sim_s": None, "reason": ""}
            goals.append(goal)
            open_goals[event.node_uid] = goal
        elif event.kind in (EventKind.GOAL_REACHED, EventKind.GOAL_FAILED):
            goal = open_goals.pop(event.node_uid, None)
            if goal is None:
                continue
            reached = event.kind == EventKind.GOAL_REACHED
            goal.update(result="reached" if reached else "failed",
                        ended_sim_s=since_start(event.sim_s, origin),
                        reason="" if reached else event.message)
    return goals


def _reason_record(event: MissionEvent, origin: Any) -> dict[str, Any]:
    """A reason event as ``mission.json`` lists it (``what``, ``uid``, ``name``...)."""
    return {"what": kind_name(event.kind), "uid": event.node_uid, "name": event.node_name,
            "kind": event.node_kind, "message": event.message,
            "sim_s": since_start(event.sim_s, origin), "wall_s": event.wall_s}


def _startup_failure(status: dict[str, Any]) -> list[dict[str, Any]]:
    """The runner's start-up failure (status file ``error``) as a failure record, if any."""
    error = status.get("error")
    if not isinstance(error, dict):
        return []
    return [{"what": "failure", "uid": "", "name": error.get("step", ""),
             "kind": "", "message": error.get("message", "")}]


def summarise(inputs: MissionInputs) -> dict[str, Any]:
    """Build the ``mission.json`` document from the run's files, then add the apps' keys.

    Every simulated time in it counts from one origin, the first tick (``sim_start_s``,
    the ROS time it had).

    Args:
        inputs: Where everything is.

    Returns:
        The document (JSON-ready).
    """
    status = _read_json(inputs.report_dir / "status.json")
    trace = read_json_lines(inputs.report_dir / "trace.jsonl")
    events = read_events(inputs.report_dir / EVENTS_FILE)
    sim_start, sim_end = status.get("sim_start_s"), status.get("sim_end_s")
    sim_duration = (sim_end - sim_start) if isinstance(sim_start, (int, float)) and \
        isinstance(sim_end, (int, float)) else None
    runner_wall = status.get("wall_duration_s")
    first_tick = status.get("wall_first_tick_s")
    ticking_wall = (runner_wall - first_tick) if isinstance(runner_wall, (int, float)) and \
        isinstance(first_tick, (int, float)) else None
    path_m = max((float(r["path_m"]) for r in trace if "path_m" in r), default=0.0)
    accepted = [r for r in trace if r.get("event") == "accepted"]
    goals = _goals(events, sim_start)
    ticks = int(status.get("ticks") or 0)
    final_position = _final_position(trace)
    last_goal, at_last_goal = _last_goal(trace, final_position)
    summary = {
        "tree": inputs.tree,
        "params": inputs.params_file,
        "outcome": inputs.outcome,
        "reason": inputs.reason,
        "root_status": status.get("status"),
        "sim_start_s": sim_start,
        "goals": goals,
        "final_position": final_position,
        "last_goal": last_goal,
        "at_last_goal": at_last_goal,
        "blocked_areas": [{"x": x, "y": y, "radius": r} for x, y, r in inputs.blocked_areas],
        "path_length_m": round(path_m, 3),
        "navigation_goals": len(accepted) if trace else len(goals),
        "sim_duration_s": round(sim_duration, 3) if sim_duration is not None else None,
        "wall_duration_s": round(inputs.wall_duration_s, 3),
        "runner_wall_duration_s": runner_wall,
        "wall_first_tick_s": first_tick,
        "ticks": ticks,
        "ticks_per_wall_s": round(ticks / ticking_wall, 2) if ticking_wall else None,
        "real_time_factor": round(sim_duration / ticking_wall, 2)
        if sim_duration is not None and ticking_wall else None,
        "failures": [_reason_record(e, sim_start) for e in events if e.kind in REASON_KINDS]
        or _startup_failure(status),
        "node_statuses": status.get("nodes", {}),
        "reloads": [{"what": kind_name(e.kind), "message": e.message,
                     "sim_s": since_start(e.sim_s, sim_start), "wall_s": e.wall_s}
                    for e in events
                    if e.kind in (EventKind.TREE_SWAPPED, EventKind.RELOAD_REFUSED)],
    }
    if status.get("entries"):
        summary["entries"] = status["entries"]  # the final blackboard entry values
    for app in report_apps(inputs):
        if app.report is not None:
            summary.update(app.report(inputs, events, summary))
    return summary


def report_apps(inputs: MissionInputs) -> Sequence[App]:
    """The apps whose parts the report adds.

    The run's, else every installed one (each adds only what the run's files show of it).
    """
    from sar_framework.app import discover_apps

    return inputs.apps if inputs.apps is not None else discover_apps()


def write_report(inputs: MissionInputs) -> list[Path]:
    """Write ``mission.json``, ``mission.png`` and ``tree.svg`` into the report folder.

    Args:
        inputs: Where everything is.

    Returns:
        The files written.
    """
    folder = inputs.report_dir
    folder.mkdir(parents=True, exist_ok=True)
    summary = summarise(inputs)
    written = [folder / "mission.json"]
    written[0].write_text(json.dumps(summary, indent=2) + "\n", encoding="utf-8")
    trace = read_json_lines(folder / "trace.jsonl")
    written.append(draw_map(summary, trace, folder / "mission.png", inputs.map_yaml,
                            report_apps(inputs)))
    if inputs.spec is not None:
        from sar_framework.engine.rendering.render import render_to_file

        statuses = summary.get("node_statuses") or {}
        written.append(render_to_file(inputs.spec, folder / "tree.svg", statuses=statuses))
    return written
