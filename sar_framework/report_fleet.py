"""``fleet.png``: every robot's path in its own colour, who searched which zone, the bids.

Plain Python (Pillow; no ROS). :func:`draw_fleet` draws a ``fleet.json`` document
(:mod:`sar_framework.orchestrate.fleet_outcome`) on the course map
(:func:`sar_framework.report_map.map_canvas`): each robot's path from its own trace
(``RUN/<name>/trace.jsonl``, the simulator writes one per robot), its spawn (hollow) and
end (filled); each zone ringed in the colour of the robot that searched it (grey when
none did) with the robot's name; and, from the zone coordinator's events file, each award
with every bid of its round in the right-hand panel (``#2 zone_b -> robot2 4.1 m``,
``   robot1: zone_b 6.0, zone_c 7.2``; path costs in metres from each robot's own planner),
plus robots lost and zones given back.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

from sar_framework.events.jsonl import read_json_lines
from sar_framework.report_map import MAP_YAML, font, label, map_canvas

ROBOT_COLOURS = ((30, 110, 220), (220, 90, 30), (40, 150, 60), (150, 60, 190),
                 (200, 40, 110), (0, 150, 160), (140, 110, 20), (90, 90, 90))
"""One colour per robot, in fleet order (repeats after eight)."""
_NONE = (160, 160, 160)
_TEXT = (25, 25, 25)
_LEGEND_W = 420


def _trace_poses(path: Path) -> list[tuple[float, float]]:
    return [(float(record["x"]), float(record["y"])) for record in read_json_lines(path)
            if "x" in record and "y" in record and record.get("event") in (None, "start")]


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


def draw_fleet(run_dir: Path, fleet: dict[str, Any], params_file: str,
               coordinator_events: Sequence[dict[str, Any]], out: Path, *,
               map_yaml: Path = MAP_YAML) -> Path:
    """Draw ``fleet.png``.

    Args:
        run_dir: The run folder (each robot's trace in ``run_dir/<name>/trace.jsonl``).
        fleet: The ``fleet.json`` document.
        params_file: The mission parameter file (zone positions).
        coordinator_events: The zone coordinator's events ([] when it did not run).
        out: The PNG file to write.
        map_yaml: The occupancy map.

    Returns:
        ``out``.
    """
    from sar_plugins.sar.report import mission_layout as read_mission_layout

    canvas = map_canvas(map_yaml, _LEGEND_W)
    draw, to_px, limit = canvas.draw, canvas.to_px, canvas.map_img.width
    small, normal, big = font(13), font(15), font(18)
    colours = {name: ROBOT_COLOURS[i % len(ROBOT_COLOURS)]
               for i, name in enumerate(fleet.get("robots", {}))}
    for name, colour in colours.items():
        poses = [to_px(x, y) for x, y in _trace_poses(run_dir / name / "trace.jsonl")]
        if len(poses) >= 2:
            draw.line(poses, fill=colour, width=3, joint="curve")
        if poses:
            (sx, sy), (ex, ey) = poses[0], poses[-1]
            draw.ellipse((sx - 6, sy - 6, sx + 6, sy + 6), outline=colour, width=2)
            draw.ellipse((ex - 4, ey - 4, ex + 4, ey + 4), fill=colour)
    zones, base = read_mission_layout(params_file)
    if "x" in base and "y" in base:
        bx, by = to_px(base["x"], base["y"])
        draw.rectangle((bx - 9, by - 9, bx + 9, by + 9), outline=(120, 70, 200), width=3)
    searched = fleet.get("zones", {})
    for zone in zones:
        by_whom = searched.get(zone["id"], {}).get("searched_by", [])
        zx, zy = to_px(zone["x"], zone["y"])
        r = 0.3 * canvas.px_per_m
        rings = [colours.get(name, _NONE) for name in by_whom] or [_NONE]
        for i, colour in enumerate(rings):
            grow = 5 * i
            draw.ellipse((zx - r - grow, zy - r - grow, zx + r + grow, zy + r + grow),
                         outline=colour, width=4)
        text = f"{zone['id']}: {', '.join(by_whom) if by_whom else 'not searched'}"
        label(draw, (zx - r, zy + r + 4 + 5 * (len(rings) - 1)), text, rings[0], small,
              limit=limit)
    title = (f"Fleet of {len(colours)}: {fleet.get('outcome', '')}  |  "
             + ("zones by auction" if fleet.get("coordinator") else "every robot walks "
                "every zone"))
    draw.text((10, 12), title, fill=_TEXT, font=big)
    _legend(draw, (limit + 14, 50), fleet, colours=colours,
            awards=award_lines(coordinator_events), normal=normal, small=small)
    out.parent.mkdir(parents=True, exist_ok=True)
    canvas.img.save(out, "PNG")
    return out


def _legend(draw: Any, xy: tuple[int, int], fleet: dict[str, Any], *,
            colours: dict[str, tuple[int, int, int]], awards: list[str], normal: Any,
            small: Any) -> None:
    """The robots (colour, verdict, time, home) and the auction's awards and bids."""
    x, y = xy
    draw.text((x, y), "Robots (path; hollow: spawn)", fill=_TEXT, font=normal)
    y += 24
    for name, colour in colours.items():
        robot = fleet["robots"][name]
        sim = robot.get("sim_duration_s")
        home = "home" if robot.get("at_base") else "not home"
        draw.line((x, y + 7, x + 22, y + 7), fill=colour, width=4)
        timing = f"{sim:.0f} s" if isinstance(sim, (int, float)) else "-"
        draw.text((x + 30, y), f"{name}: {robot.get('outcome')}, {timing}, {home}",
                  fill=_TEXT, font=small)
        y += 20
    y += 12
    draw.text((x, y), "Auction rounds: awards, bids (m)" if awards else "No auction "
              "(no coordinator)", fill=_TEXT, font=normal)
    y += 24
    for line in awards[:28]:
        draw.text((x, y), line, fill=_TEXT, font=small)
        y += 18
    if len(awards) > 28:
        draw.text((x, y), f"... {len(awards) - 28} more (fleet_events.jsonl)", fill=_TEXT,
                  font=small)
