"""The search-and-rescue app's part of the report: zones, base station and survivors.

Added to ``mission.json`` by :func:`mission_report` (the app's ``report`` hook), from the
mission parameter file (:func:`mission_layout`), the runner's
events and the report server's ``reports.jsonl``. Simulated times count from the mission's
one origin, its first tick (``sim_start_s``), as every figure of the report does.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from sar_plugins.sar.events import SAR_KINDS, SarKind

from sar_framework.events.event import MissionEvent
from sar_framework.events.jsonl import read_json_lines

AT_BASE_M = 0.5
"""A robot ending this close to the base station (metres) is at base."""


def _natural_key(text: str) -> tuple[str, int]:
    match = re.match(r"^(.*?)(\d+)$", text)
    return (match.group(1), int(match.group(2))) if match else (text, 0)


def mission_layout(params_file: str | Path) -> tuple[list[dict[str, Any]], dict[str, Any]]:
    """Read the planned zones and the base station from a ROS 2 parameter file.

    Args:
        params_file: The file (``/**: ros__parameters: {zone_order, zones, base_station}``).

    Returns:
        ``(zones, base)``: zones as ``{id, x, y, yaw}`` in visiting order, base ``{x, y, yaw}``.
        Missing pieces come back empty; the runner has already validated the file.
    """
    from sar_framework.report import numbers, read_ros_parameters

    params = read_ros_parameters(params_file)
    table = params.get("zones") if isinstance(params.get("zones"), dict) else {}
    order = params.get("zone_order") or list(table)
    zones = [{"id": z, **numbers(table[z])} for z in order if isinstance(table.get(z), dict)]
    return zones, numbers(params.get("base_station"))


def survivors(report_dir: Path, events: Sequence[MissionEvent],
              since_start: Any = lambda s: s) -> list[dict[str, Any]]:
    """Survivors broadcast, acknowledged (events, report file) or refused (events).

    Args:
        report_dir: The report folder (its ``reports.jsonl``).
        events: The runner's events.
        since_start: Turns an event's ROS time into the report's simulated time.
    """
    found: dict[str, dict[str, Any]] = {}

    def entry(event: MissionEvent) -> dict[str, Any]:
        x, y, _ = event.position or (None, None, None)
        survivor_id = event.value("survivor_id")
        return found.setdefault(survivor_id, {
            "id": survivor_id, "x": x, "y": y, "frame": "map", "found_sim_s": None,
            "acknowledged": False})

    for event in events:
        if event.kind == SarKind.SURVIVOR_BROADCAST:
            survivor = entry(event)
            if survivor["found_sim_s"] is None:
                survivor["found_sim_s"] = since_start(event.sim_s)
        elif event.kind == SarKind.SURVIVOR_REPORTED:
            survivor = entry(event)
            survivor.pop("refused", None)
            survivor["acknowledged"] = True
        elif event.kind == SarKind.SURVIVOR_REFUSED:
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


def mission_report(inputs: Any, events: Sequence[MissionEvent],
                   document: dict[str, Any]) -> dict[str, Any]:
    """The app's keys of ``mission.json``: zones planned, visited and skipped, the base, survivors.

    Args:
        inputs: The report's :class:`~sar_framework.report.MissionInputs`.
        events: The runner's events.
        document: The core's ``mission.json`` so far (its ``final_position``, its clock).

    Returns:
        The keys to add ({} when the run has no zones and no event of the app).
    """
    from sar_framework.report import since_start

    zones, base = mission_layout(inputs.params_file) if inputs.params_file else ([], {})
    base = dict(inputs.base) if inputs.base is not None else base
    if not zones and not any(e.kind in SAR_KINDS for e in events):
        return {}
    origin = document.get("sim_start_s")
    visited: list[dict[str, Any]] = []
    base_reached: dict[str, Any] | None = None
    planned = {z["id"]: z for z in zones}
    for event in events:
        if event.kind not in (SarKind.ZONE_REACHED, SarKind.BASE_REACHED):
            continue
        times = {"arrival_sim_s": since_start(event.sim_s, origin),
                 "arrival_wall_s": event.wall_s}
        if event.kind == SarKind.BASE_REACHED:
            base_reached = {**base, **times}
        else:
            zone_id = event.value("zone_id")
            visited.append({**planned.get(zone_id, {"id": zone_id}), **times})
    final = document.get("final_position")
    at_base = (math.hypot(final["x"] - base["x"], final["y"] - base["y"]) <= AT_BASE_M
               if final and "x" in base and "y" in base else None)
    return {
        "zones_planned": zones,
        "zones_visited": visited,
        "zones_skipped": [z["id"] for z in zones if z["id"] not in {v["id"] for v in visited}],
        "base_station": base,
        "base_reached": base_reached,
        "at_base": at_base,
        "survivors": survivors(inputs.report_dir, events,
                               lambda s: since_start(s, origin)),
    }


def progress_line(event: MissionEvent) -> str | None:
    """The console line of one of the app's events (``sar-tree run``), or None."""
    if event.kind not in SAR_KINDS:
        return None
    if event.kind == SarKind.SURVIVOR_REFUSED:  # its message is the base's reason alone
        return f"Report for {event.value('survivor_id')} refused by base: {event.message}"
    return event.message


def summary_parts(document: dict[str, Any]) -> list[str]:
    """The app's words in ``sar-tree run``'s summary line, from ``mission.json``."""
    if "zones_planned" not in document:
        return []
    zones = list(dict.fromkeys(z["id"] for z in document.get("zones_visited", [])))
    reported = [s["id"] for s in document.get("survivors", []) if s.get("acknowledged")]
    parts = [f"zones visited: {', '.join(zones) or 'none'}"]
    if document.get("zones_skipped"):
        parts.append(f"zones not reached: {', '.join(document['zones_skipped'])}")
    parts.append(f"survivors reported: {', '.join(reported) or 'none'}")
    return parts
