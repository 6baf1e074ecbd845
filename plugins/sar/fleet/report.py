"""The search-and-rescue app's part of a fleet's report: who searched which zone, the bids.

:func:`fleet_report` adds to ``fleet.json``: ``coordinator`` (whether the zones were
auctioned), ``base_station`` (the mission's; each robot's home is its spawn place), ``zones`` (each
with the robots that searched it: the coordinator's
``searched`` events when it ran, else every robot that reached it) and each robot's
``zones_visited`` and ``at_base``; its problems fail the run: a zone never searched, one
searched twice when the coordinator shared them out, a robot that succeeded away from home.
:func:`fleet_figure` rings each zone in its searchers' colours on ``fleet.png``, marks the
base and lists the coordinator's awards, each with its round's bids.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from sar_plugins.sar.fleet.processes import COORDINATOR_EVENTS_FILE, uses_coordinator

from sar_framework.events.jsonl import read_json_lines
from sar_framework.mission.processes import MissionSettings
from sar_framework.report_map import MapCanvas, MapLayer, font, label

_NONE = (160, 160, 160)
_BASE = (120, 70, 200)
MAX_AWARD_LINES = 28
"""The awards and bids the picture's panel shows (the rest: the events file)."""


def zone_searchers(zone_ids: Sequence[str], summaries: Mapping[str, dict[str, Any]],
                   coordinator_events: Sequence[dict[str, Any]] | None
                   ) -> dict[str, list[str]]:
    """Zone id -> the robots that searched it, in order.

    Args:
        zone_ids: The mission's zones.
        summaries: Robot name -> its ``mission.json``.
        coordinator_events: The coordinator's events, or None when it did not run (then a
            zone is searched by every robot that reached it).
    """
    searched: dict[str, list[str]] = {zone: [] for zone in zone_ids}
    if coordinator_events is not None:
        for event in coordinator_events:
            if event.get("kind") == "searched":
                searched.setdefault(str(event.get("zone_id", "")), []).append(
                    str(event.get("robot", "")))
        return searched
    for name, summary in summaries.items():
        for zone in dict.fromkeys(z["id"] for z in summary.get("zones_visited", [])):
            searched.setdefault(zone, []).append(name)
    return searched


def zone_problems(searched: Mapping[str, list[str]], summaries: Mapping[str, dict[str, Any]],
                  *, once: bool) -> list[str]:
    """Zones never searched (or twice, ``once``), robots that ended away from home."""
    problems = []
    for zone, by in searched.items():
        if not by:
            problems.append(f"{zone} was never searched")
        elif once and len(by) > 1:
            problems.append(f"{zone} was searched {len(by)} times ({', '.join(by)})")
    for name, summary in summaries.items():
        if summary.get("outcome", "SUCCESS") == "SUCCESS" and "at_base" in summary \
                and summary.get("at_base") is not True:
            final = summary.get("final_position")
            where = f" (ends at ({final['x']:.2f}, {final['y']:.2f}))" if final else ""
            problems.append(f"{name} is not home{where}")
    return problems


def fleet_report(settings: MissionSettings, summaries: Mapping[str, dict[str, Any]]
                 ) -> tuple[dict[str, Any], list[str]]:
    """The app's keys of ``fleet.json`` and its problems ({} and [] without zones)."""
    zones = next((s["zones_planned"] for s in summaries.values() if "zones_planned" in s), None)
    if zones is None:
        return {}, []
    coordinator = uses_coordinator(settings)
    events = (read_json_lines(Path(settings.run_folder) / COORDINATOR_EVENTS_FILE)
              if coordinator else None)
    searched = zone_searchers([z["id"] for z in zones], summaries, events)
    base = {}
    if settings.params_file:
        from sar_plugins.sar.report import mission_layout

        base = mission_layout(settings.params_file)[1]
    keys = {"coordinator": coordinator, "base_station": base,
            "zones": {zone: {"searched_by": list(by)} for zone, by in searched.items()},
            "robots": {name: {"zones_visited": [z["id"] for z in s.get("zones_visited", [])],
                              "at_base": s.get("at_base")} for name, s in summaries.items()}}
    return keys, zone_problems(searched, summaries, once=coordinator)


def _cost(cost: Any) -> str:
    """A bid as drawn: metres, or ``unreachable`` (``null``: the robot has no path)."""
    return f"{float(cost):.1f} m" if isinstance(cost, (int, float)) else "unreachable"


def _round_bids(bids: dict[tuple[Any, str], dict[str, float | None]], auction: Any
                ) -> list[str]:
    """``   robot1: zone_d 2.5, zone_a 7.1`` per bidder of round ``auction``."""
    by_robot: dict[str, list[str]] = {}
    for (round_id, zone), offers in bids.items():
        if round_id == auction and zone:
            for robot, cost in offers.items():
                by_robot.setdefault(robot, []).append(
                    f"{zone} {cost:.1f}" if cost is not None else f"{zone} -")
    return [f"   {robot}: {', '.join(offers)}" for robot, offers in sorted(by_robot.items())]


def award_lines(events: Sequence[dict[str, Any]]) -> list[str]:
    """The coordinator's awards, each with the other bids on that zone, and its losses.

    Args:
        events: The coordinator's JSON Lines events (kinds ``bid``, ``award``,
            ``robot_lost``, ``given_back``, ``abandoned``).

    Returns:
        Per award ``#2 zone_b -> robot2 4.1 m`` and, under a round's first award, every
        bid of that round (``   robot1: zone_b 6.0, zone_c -``; ``-``: unreachable), or a
        line for another notable event.
    """
    bids: dict[tuple[Any, str], dict[str, float | None]] = {}  # (round, zone) -> bids
    lines = []
    for event in events:
        kind, robot, zone = event.get("kind"), str(event.get("robot", "")), \
            str(event.get("zone_id", ""))
        auction = event.get("auction_id")
        if kind == "bid":
            for zone_id, cost in zip(event.get("zone_ids") or [], event.get("costs") or [],
                                     strict=False):
                bids.setdefault((auction, str(zone_id)), {})[robot] = \
                    float(cost) if isinstance(cost, (int, float)) else None
        elif kind == "award":
            costs = event.get("costs") or []
            own = f" {_cost(costs[0])}" if costs else ""
            lines.append(f"#{auction} {zone} -> {robot}{own}")
            if (auction, "") not in bids:  # the round's bids, once, under its first award
                bids[(auction, "")] = {}
                lines += _round_bids(bids, auction)
        elif kind == "robot_lost":
            lines.append(f"{robot} lost" + (f": {event['message']}" if event.get("message")
                                            else ""))
        elif kind == "given_back":
            lines.append(f"{zone} given back by {robot}")
        elif kind == "abandoned":
            lines.append(f"{zone} abandoned")
    return lines


def fleet_figure(canvas: MapCanvas, document: dict[str, Any], run_folder: Path,
                 colours: Mapping[str, tuple[int, int, int]]) -> MapLayer | None:
    """Ring each zone in its searchers' colours, mark the base, list the awards and bids."""
    if "zones" not in document:
        return None
    draw, to_px, limit = canvas.draw, canvas.to_px, canvas.map_img.width
    small = font(13)
    planned: dict[str, dict[str, Any]] = {}
    for name in document.get("robots", {}):
        summary = _mission(run_folder / name / "mission.json")
        planned.update({z["id"]: z for z in summary.get("zones_planned", [])})
    base = document.get("base_station") or {}
    if "x" in base and "y" in base:
        bx, by = to_px(base["x"], base["y"])
        draw.rectangle((bx - 9, by - 9, bx + 9, by + 9), outline=_BASE, width=3)
    for zone_id, zone in planned.items():
        by_whom = document["zones"].get(zone_id, {}).get("searched_by", [])
        zx, zy = to_px(zone["x"], zone["y"])
        r = 0.3 * canvas.px_per_m
        rings = [colours.get(name, _NONE) for name in by_whom] or [_NONE]
        for i, colour in enumerate(rings):
            grow = 5 * i
            draw.ellipse((zx - r - grow, zy - r - grow, zx + r + grow, zy + r + grow),
                         outline=colour, width=4)
        text = f"{zone_id}: {', '.join(by_whom) if by_whom else 'not searched'}"
        label(draw, (zx - r, zy + r + 4 + 5 * (len(rings) - 1)), text, rings[0], small,
              limit=limit)
    coordinator = bool(document.get("coordinator"))
    awards = award_lines(read_json_lines(run_folder / COORDINATOR_EVENTS_FILE)
                         if coordinator else [])
    lines = ["Auction rounds: awards, bids (m)" if awards else
             "No auction (no coordinator)", *awards[:MAX_AWARD_LINES]]
    if len(awards) > MAX_AWARD_LINES:
        lines.append(f"... {len(awards) - MAX_AWARD_LINES} more ({COORDINATOR_EVENTS_FILE})")
    return MapLayer(title="zones by auction" if coordinator else "every robot walks every zone",
                    lines=lines)


def _mission(path: Path) -> dict[str, Any]:
    import json

    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
