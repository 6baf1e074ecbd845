"""The mission report: ``mission.json``, ``mission.png`` and ``tree.svg`` in the report folder.

Plain Python (no ROS). It reads what the mission's processes left in the report folder:

- ``events.jsonl``: the runner's events (:mod:`sar_framework.events`): zones reached and
  not, the base reached, survivors broadcast, reported and refused, failures;
- ``status.json``: the runner's status file (docs/reference/mission-contracts.md): node statuses,
  ticks, clock readings, the final blackboard entry values (copied as ``entries``);
- ``trace.jsonl``: the simulator's trace (robot poses, goal events, path length), if any;
- ``reports.jsonl``: the report server's acknowledged survivors;

plus the mission parameter file (zones, base station) and the course map. ``mission.png``
draws the occupancy map (walls and debris), the planned zones (numbered in visiting
order, with arrival times), the base station, the survivors with their ids, blocked areas
and the robot's path, with a title and a legend (:mod:`sar_framework.report_map`).
``tree.svg`` is the tree coloured by each node's last status
(:func:`sar_framework.engine.rendering.render.render_to_file`).
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

from sar_framework.events.event import REASON_KINDS, EventKind, MissionEvent
from sar_framework.events.jsonl import EVENTS_FILE, read_events, read_json_lines
from sar_framework.report_map import MAP_YAML, draw_map

AT_BASE_M = 0.5
"""A robot ending this close to the base station (metres) is at base."""


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
        map_yaml: The map to draw on.
        blocked_areas: Injected obstacles as ``(x, y, radius)`` metres, drawn on the map.
        base: ``{x, y, yaw}`` of this robot's base over the parameter file's (a fleet's
            robot goes home to its own spawn place).
    """

    report_dir: Path
    tree: str
    params_file: str
    spec: Any
    outcome: str
    reason: str = ""
    wall_duration_s: float = 0.0
    map_yaml: Path = MAP_YAML
    blocked_areas: tuple[tuple[float, float, float], ...] = ()
    base: dict[str, float] | None = None


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


def read_mission_layout(params_file: str | Path) -> tuple[list[dict[str, Any]], dict[str, Any]]:
    """Read the planned zones and the base station from a ROS 2 parameter file.

    Args:
        params_file: The file (``/**: ros__parameters: {zone_order, zones, base_station}``).

    Returns:
        ``(zones, base)``: zones as ``{id, x, y, yaw}`` in visiting order, base ``{x, y, yaw}``.
        Missing pieces come back empty; the runner has already validated the file.
    """
    try:
        doc = yaml.safe_load(Path(params_file).read_text(encoding="utf-8"))
    except (OSError, yaml.YAMLError):
        return [], {}
    params: dict[str, Any] = {}
    for section in (doc or {}).values() if isinstance(doc, dict) else ():
        if isinstance(section, dict) and isinstance(section.get("ros__parameters"), dict):
            _merge(params, section["ros__parameters"])
    table = params.get("zones") if isinstance(params.get("zones"), dict) else {}
    order = params.get("zone_order") or list(table)
    zones = [{"id": z, **_numbers(table[z])} for z in order if isinstance(table.get(z), dict)]
    base = params.get("base_station") if isinstance(params.get("base_station"), dict) else {}
    return zones, _numbers(base)


def _numbers(pose: dict[str, Any]) -> dict[str, float]:
    """The numeric entries of a pose mapping (a bad value is left out, never an error)."""
    return {k: float(v) for k, v in pose.items()
            if isinstance(v, (int, float)) and not isinstance(v, bool)}


def _final_position(trace: Sequence[dict[str, Any]], base: dict[str, float]
                    ) -> tuple[dict[str, float] | None, bool | None]:
    """The robot's last traced position and whether it is within :data:`AT_BASE_M` of base."""
    poses = [r for r in trace if "x" in r and "y" in r and r.get("event") in (None, "start")]
    if not poses:
        return None, None
    x, y = float(poses[-1]["x"]), float(poses[-1]["y"])
    at_base = (math.hypot(x - base["x"], y - base["y"]) <= AT_BASE_M
               if "x" in base and "y" in base else None)
    return {"x": round(x, 3), "y": round(y, 3)}, at_base


def _last_goal(trace: Sequence[dict[str, Any]], final: dict[str, float] | None
               ) -> tuple[dict[str, float] | None, bool | None]:
    """Where the last navigation goal sent the robot, and whether it is within reach of it."""
    goals = [r for r in trace if r.get("event") == "accepted" and "x" in r and "y" in r]
    if not goals:
        return None, None
    x, y = float(goals[-1]["x"]), float(goals[-1]["y"])
    at_goal = (math.hypot(x - final["x"], y - final["y"]) <= AT_BASE_M
               if final is not None else None)
    return {"x": round(x, 3), "y": round(y, 3)}, at_goal


def _survivors(report_dir: Path, events: Sequence[MissionEvent]) -> list[dict[str, Any]]:
    """Survivors broadcast, acknowledged (events, report file) or refused (events)."""
    found: dict[str, dict[str, Any]] = {}

    def entry(event: MissionEvent) -> dict[str, Any]:
        x, y, _ = event.position or (None, None, None)
        return found.setdefault(event.survivor_id, {
            "id": event.survivor_id, "x": x, "y": y, "frame": "map", "found_sim_s": None,
            "acknowledged": False})

    for event in events:
        if event.kind == EventKind.SURVIVOR_BROADCAST:
            survivor = entry(event)
            if survivor["found_sim_s"] is None:
                survivor["found_sim_s"] = event.sim_s
        elif event.kind == EventKind.SURVIVOR_REPORTED:
            survivor = entry(event)
            survivor.pop("refused", None)
            survivor["acknowledged"] = True
        elif event.kind == EventKind.SURVIVOR_REFUSED:
            survivor = entry(event)
            if not survivor["acknowledged"]:
                survivor["refused"] = event.message
    for record in read_json_lines(report_dir / "reports.jsonl"):
        sid = str(record.get("survivor_id", ""))
        survivor = found.setdefault(sid, {"id": sid, "found_sim_s": None})
        survivor.pop("refused", None)
        survivor.update({"x": record.get("x"), "y": record.get("y"),
                         "frame": record.get("frame_id", "map"), "acknowledged": True})
    return sorted(found.values(), key=lambda s: _natural_key(s["id"]))


def _reason_record(event: MissionEvent) -> dict[str, Any]:
    """A reason event as ``mission.json`` lists it (``what``, ``uid``, ``name``...)."""
    return {"what": event.kind.value, "uid": event.node_uid, "name": event.node_name,
            "kind": event.node_kind, "message": event.message, "sim_s": event.sim_s,
            "wall_s": event.wall_s}


def _natural_key(text: str) -> tuple[str, int]:
    match = re.match(r"^(.*?)(\d+)$", text)
    return (match.group(1), int(match.group(2))) if match else (text, 0)


def _startup_failure(status: dict[str, Any]) -> list[dict[str, Any]]:
    """The runner's start-up failure (status file ``error``) as a failure record, if any."""
    error = status.get("error")
    if not isinstance(error, dict):
        return []
    return [{"what": "failure", "uid": "", "name": error.get("step", ""),
             "kind": "", "message": error.get("message", "")}]


def summarise(inputs: MissionInputs) -> dict[str, Any]:
    """Build the ``mission.json`` document from the run's files.

    Args:
        inputs: Where everything is.

    Returns:
        The document (JSON-ready).
    """
    status = _read_json(inputs.report_dir / "status.json")
    trace = read_json_lines(inputs.report_dir / "trace.jsonl")
    events = read_events(inputs.report_dir / EVENTS_FILE)
    zones, base = read_mission_layout(inputs.params_file)
    base = dict(inputs.base) if inputs.base is not None else base
    visited: list[dict[str, Any]] = []
    base_reached: dict[str, Any] | None = None
    planned = {z["id"]: z for z in zones}
    sim_start, sim_end = status.get("sim_start_s"), status.get("sim_end_s")
    for event in events:
        if event.kind not in (EventKind.ZONE_REACHED, EventKind.BASE_REACHED):
            continue
        # Simulated times from the mission's start, like sim_duration_s (ROS time is not 0
        # at the first tick).
        arrival: float | None = event.sim_s
        if isinstance(sim_start, (int, float)):
            arrival = round(event.sim_s - sim_start, 3)
        times = {"arrival_sim_s": arrival, "arrival_wall_s": event.wall_s}
        if event.kind == EventKind.BASE_REACHED:
            base_reached = {**base, **times}
        else:
            visited.append({**planned.get(event.zone_id, {"id": event.zone_id}), **times})
    sim_duration = (sim_end - sim_start) if isinstance(sim_start, (int, float)) and \
        isinstance(sim_end, (int, float)) else None
    runner_wall = status.get("wall_duration_s")
    first_tick = status.get("wall_first_tick_s")
    ticking_wall = (runner_wall - first_tick) if isinstance(runner_wall, (int, float)) and \
        isinstance(first_tick, (int, float)) else None
    path_m = max((float(r["path_m"]) for r in trace if "path_m" in r), default=0.0)
    goals = [r for r in trace if r.get("event") == "accepted"]
    ticks = int(status.get("ticks") or 0)
    final_position, at_base = _final_position(trace, base)
    last_goal, at_last_goal = _last_goal(trace, final_position)
    summary = {
        "tree": inputs.tree,
        "params": inputs.params_file,
        "outcome": inputs.outcome,
        "reason": inputs.reason,
        "root_status": status.get("status"),
        "zones_planned": zones,
        "zones_visited": visited,
        "zones_skipped": [z["id"] for z in zones if z["id"] not in {v["id"] for v in visited}],
        "base_station": base,
        "base_reached": base_reached,
        "final_position": final_position,
        "at_base": at_base,
        "last_goal": last_goal,
        "at_last_goal": at_last_goal,
        "blocked_areas": [{"x": x, "y": y, "radius": r} for x, y, r in inputs.blocked_areas],
        "survivors": _survivors(inputs.report_dir, events),
        "path_length_m": round(path_m, 3),
        "navigation_goals": len(goals),
        "sim_duration_s": round(sim_duration, 3) if sim_duration is not None else None,
        "wall_duration_s": round(inputs.wall_duration_s, 3),
        "runner_wall_duration_s": runner_wall,
        "wall_first_tick_s": first_tick,
        "ticks": ticks,
        "ticks_per_wall_s": round(ticks / ticking_wall, 2) if ticking_wall else None,
        "real_time_factor": round(sim_duration / ticking_wall, 2)
        if sim_duration is not None and ticking_wall else None,
        "failures": [_reason_record(e) for e in events if e.kind in REASON_KINDS]
        or _startup_failure(status),
        "node_statuses": status.get("nodes", {}),
        "reloads": [{"what": e.kind.value, "message": e.message, "sim_s": e.sim_s,
                     "wall_s": e.wall_s} for e in events
                    if e.kind in (EventKind.TREE_SWAPPED, EventKind.RELOAD_REFUSED)],
    }
    if status.get("entries"):
        summary["entries"] = status["entries"]  # the final blackboard entry values
    return summary


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
    written.append(draw_map(summary, trace, folder / "mission.png", inputs.map_yaml))
    if inputs.spec is not None:
        from sar_framework.engine.rendering.render import render_to_file

        statuses = summary.get("node_statuses") or {}
        written.append(render_to_file(inputs.spec, folder / "tree.svg", statuses=statuses))
    return written
