"""The mission report: ``mission.json``, ``mission.png`` and ``tree.svg`` in the report folder.

Plain Python (no ROS). It reads what the mission's processes left in the report folder:

- ``status.json``: the runner's status file (docs/mission-contracts.md): node statuses,
  leaf events (``Reached zone_a.`` with its simulated time), failures, ticks;
- ``trace.jsonl``: the simulator's trace (robot poses, goal events, path length), if any;
- ``reports.jsonl``: the report server's acknowledged survivors;
- ``report.log``: the report server's log, for refused reports;

plus the mission parameter file (zones, base station) and the course map. ``mission.png``
draws the occupancy map (walls and debris), the planned zones (numbered in visiting
order, with arrival times), the base station, the survivors with their ids, and the
robot's path, with a title and a legend. ``tree.svg`` is the tree coloured by each node's
last status (:func:`sar_framework.engine.render.render_to_file`).
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

MAP_YAML = Path(__file__).resolve().parents[1] / "maps" / "final_project_map.yaml"
"""The course map the report draws on."""

_REACHED = re.compile(r"^Reached (.+)\.$")
_BROADCAST = re.compile(r"map -> (\S+) at \((-?[0-9.]+), (-?[0-9.]+)\)")
_REFUSED = re.compile(r"Report refused: '([^']*)' at \((-?[0-9.]+), (-?[0-9.]+)\): (.*)$")
BASE_NAME = "base station"


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
    """

    report_dir: Path
    tree: str
    params_file: str
    spec: Any
    outcome: str
    reason: str = ""
    wall_duration_s: float = 0.0
    map_yaml: Path = MAP_YAML


# -- reading ------------------------------------------------------------------------------
def _read_json(path: Path) -> dict[str, Any]:
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
    return data if isinstance(data, dict) else {}


def _read_jsonl(path: Path) -> list[dict[str, Any]]:
    records: list[dict[str, Any]] = []
    try:
        text = path.read_text(encoding="utf-8")
    except OSError:
        return records
    for line in text.splitlines():
        try:
            record = json.loads(line)
        except ValueError:
            continue  # a line being written when we read
        if isinstance(record, dict):
            records.append(record)
    return records


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
    zones = [{"id": z, **{k: float(v) for k, v in table[z].items()}}
             for z in order if isinstance(table.get(z), dict)]
    base = params.get("base_station") if isinstance(params.get("base_station"), dict) else {}
    return zones, {k: float(v) for k, v in base.items()}


def _survivors(report_dir: Path, events: Sequence[dict[str, Any]]) -> list[dict[str, Any]]:
    """Survivors found (broadcast), acknowledged (report file) or refused (report log)."""
    found: dict[str, dict[str, Any]] = {}
    for event in events:
        match = _BROADCAST.search(str(event.get("message", "")))
        if match and event.get("status") == "SUCCESS":
            found.setdefault(match.group(1), {
                "id": match.group(1), "x": float(match.group(2)), "y": float(match.group(3)),
                "frame": "map", "found_sim_s": event.get("sim_s"), "acknowledged": False})
    for record in _read_jsonl(report_dir / "reports.jsonl"):
        sid = str(record.get("survivor_id", ""))
        entry = found.setdefault(sid, {"id": sid, "found_sim_s": None})
        entry.update({"x": record.get("x"), "y": record.get("y"),
                      "frame": record.get("frame_id", "map"), "acknowledged": True})
    try:
        log = (report_dir / "report.log").read_text(encoding="utf-8", errors="replace")
    except OSError:
        log = ""
    for line in log.splitlines():
        match = _REFUSED.search(line)
        if match and not found.get(match.group(1), {}).get("acknowledged"):
            entry = found.setdefault(match.group(1), {
                "id": match.group(1), "x": float(match.group(2)), "y": float(match.group(3)),
                "frame": "map", "found_sim_s": None})
            entry.update({"acknowledged": False, "refused": match.group(4)})
    return sorted(found.values(), key=lambda s: _natural_key(s["id"]))


def _natural_key(text: str) -> tuple[str, int]:
    match = re.match(r"^(.*?)(\d+)$", text)
    return (match.group(1), int(match.group(2))) if match else (text, 0)


def summarise(inputs: MissionInputs) -> dict[str, Any]:
    """Build the ``mission.json`` document from the run's files.

    Args:
        inputs: Where everything is.

    Returns:
        The document (JSON-ready).
    """
    status = _read_json(inputs.report_dir / "status.json")
    trace = _read_jsonl(inputs.report_dir / "trace.jsonl")
    zones, base = read_mission_layout(inputs.params_file)
    events = [e for e in status.get("events", []) if isinstance(e, dict)]
    visited: list[dict[str, Any]] = []
    base_reached: dict[str, Any] | None = None
    planned = {z["id"]: z for z in zones}
    for event in events:
        match = _REACHED.match(str(event.get("message", "")))
        if not match or event.get("status") != "SUCCESS":
            continue
        times = {"arrival_sim_s": event.get("sim_s"), "arrival_wall_s": event.get("wall_s")}
        if match.group(1) == BASE_NAME:
            base_reached = {**base, **times}
        else:
            zone = planned.get(match.group(1), {"id": match.group(1)})
            visited.append({**zone, **times})
    sim_start, sim_end = status.get("sim_start_s"), status.get("sim_end_s")
    sim_duration = (sim_end - sim_start) if isinstance(sim_start, (int, float)) and \
        isinstance(sim_end, (int, float)) else None
    runner_wall = status.get("wall_duration_s")
    first_tick = status.get("wall_first_tick_s")
    ticking_wall = (runner_wall - first_tick) if isinstance(runner_wall, (int, float)) and \
        isinstance(first_tick, (int, float)) else None
    path_m = max((float(r["path_m"]) for r in trace if "path_m" in r), default=0.0)
    goals = [r for r in trace if r.get("event") == "accepted"]
    ticks = int(status.get("ticks") or 0)
    return {
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
        "failures": status.get("failures", []),
        "node_statuses": status.get("nodes", {}),
    }


# -- drawing ------------------------------------------------------------------------------
_SCALE = 3  # pixels per map cell (0.05 m -> 60 px per metre)
_MARGIN_TOP = 44
_LEGEND_W = 250
_COLOURS = {
    "free": (250, 250, 247), "occupied": (55, 60, 68), "unknown": (205, 205, 205),
    "path": (30, 110, 220), "start": (30, 110, 220), "zone_visited": (46, 160, 67),
    "zone_skipped": (220, 60, 50), "base": (120, 70, 200), "survivor": (230, 120, 0),
    "text": (25, 25, 25), "panel": (255, 255, 255), "grid": (232, 232, 228),
}


def _star(cx: float, cy: float, radius: float) -> list[tuple[float, float]]:
    """The ten corners of a five-pointed star centred on ``(cx, cy)``."""
    return [(cx + radius * (1 if i % 2 == 0 else 0.45) * math.cos(math.pi / 2 + i * math.pi / 5),
             cy - radius * (1 if i % 2 == 0 else 0.45) * math.sin(math.pi / 2 + i * math.pi / 5))
            for i in range(10)]


def shift_into(left: float, right: float, limit: float) -> float:
    """How far to move a label spanning ``left..right`` left so it ends before ``limit``.

    Args:
        left: The label's left edge (px).
        right: The label's right edge (px).
        limit: The first pixel it must not reach (the legend panel starts there).

    Returns:
        The shift (>= 0), never so large that the label leaves the image on the left.
    """
    return max(0.0, min(right - limit, left))


def _label(draw: Any, xy: tuple[float, float], text: str, colour: Any, font: Any, *,
           limit: float) -> None:
    """Draw ``text`` on a white box so the path under it does not hide it.

    The label is moved left when it would run into the legend panel at ``limit``.
    """
    box = draw.textbbox(xy, text, font=font)
    dx = shift_into(box[0] - 2, box[2] + 2, limit)
    xy = (xy[0] - dx, xy[1])
    box = (box[0] - dx, box[1], box[2] - dx, box[3])
    draw.rectangle((box[0] - 2, box[1] - 1, box[2] + 2, box[3] + 1), fill=(255, 255, 255))
    draw.text(xy, text, fill=colour, font=font)


def _font(size: int) -> Any:
    from PIL import ImageFont

    try:
        return ImageFont.load_default(size=size)
    except TypeError:  # Pillow < 10.1: a fixed bitmap font
        return ImageFont.load_default()


def draw_map(summary: dict[str, Any], trace: Sequence[dict[str, Any]], out: Path,
             map_yaml: Path = MAP_YAML) -> Path:
    """Draw ``mission.png``: map, zones, base, survivors, path, title and legend.

    Args:
        summary: The ``mission.json`` document.
        trace: The simulator's trace records (poses are drawn as the path).
        out: The PNG file to write.
        map_yaml: The occupancy map.

    Returns:
        ``out``.
    """
    import numpy as np
    from PIL import Image, ImageDraw

    from sar_framework.sim.occupancy import FREE, OCCUPIED, load_map

    grid = load_map(map_yaml)
    rgb = np.empty((grid.height, grid.width, 3), dtype=np.uint8)
    rgb[:] = _COLOURS["unknown"]
    rgb[grid.data == FREE] = _COLOURS["free"]
    rgb[grid.data == OCCUPIED] = _COLOURS["occupied"]
    map_img = Image.fromarray(rgb[::-1], "RGB").resize(
        (grid.width * _SCALE, grid.height * _SCALE), Image.NEAREST)
    width = map_img.width + _LEGEND_W
    height = max(map_img.height + _MARGIN_TOP, 420)
    img = Image.new("RGB", (width, height), _COLOURS["panel"])
    img.paste(map_img, (0, _MARGIN_TOP))
    draw = ImageDraw.Draw(img)
    px_per_m = _SCALE / grid.resolution

    def to_px(x: float, y: float) -> tuple[float, float]:
        col = (x - grid.origin_x) * px_per_m
        row = (grid.origin_y + grid.height * grid.resolution - y) * px_per_m
        return col, row + _MARGIN_TOP

    # a 1 m grid, under everything else
    for gx in range(math.ceil(grid.origin_x), math.floor(grid.origin_x + grid.width *
                                                          grid.resolution) + 1):
        x0, _ = to_px(gx, 0)
        for y in range(_MARGIN_TOP, _MARGIN_TOP + map_img.height, 6):
            if img.getpixel((int(x0), y)) == _COLOURS["free"]:
                draw.point((int(x0), y), fill=_COLOURS["grid"])
    small, normal, big = _font(13), _font(15), _font(18)

    poses = [to_px(float(r["x"]), float(r["y"])) for r in trace
             if "event" not in r and "x" in r and "y" in r]
    start = next((r for r in trace if r.get("event") == "start"), None)
    if start is not None:
        poses.insert(0, to_px(float(start["x"]), float(start["y"])))
    if len(poses) >= 2:
        draw.line(poses, fill=_COLOURS["path"], width=3, joint="curve")
    if poses:
        sx, sy = poses[0]
        draw.ellipse((sx - 5, sy - 5, sx + 5, sy + 5), outline=_COLOURS["start"], width=2)
        ex, ey = poses[-1]
        draw.ellipse((ex - 5, ey - 5, ex + 5, ey + 5), fill=_COLOURS["path"])

    base = summary.get("base_station") or {}
    if "x" in base and "y" in base:
        bx, by = to_px(base["x"], base["y"])
        draw.rectangle((bx - 11, by - 11, bx + 11, by + 11), outline=_COLOURS["base"], width=3)
        _label(draw, (bx + 14, by + 4), "base", _COLOURS["base"], normal, limit=map_img.width)

    visited = {v["id"]: v for v in summary.get("zones_visited", [])}
    for number, zone in enumerate(summary.get("zones_planned", []), 1):
        zx, zy = to_px(zone["x"], zone["y"])
        reached = visited.get(zone["id"])
        colour = _COLOURS["zone_visited"] if reached else _COLOURS["zone_skipped"]
        r = 0.3 * px_per_m
        draw.ellipse((zx - r, zy - r, zx + r, zy + r), outline=colour, width=3)
        draw.text((zx, zy), str(number), fill=colour, font=normal, anchor="mm")
        label = zone["id"]
        label += (f"  t={reached['arrival_sim_s']:.0f}s"
                  if reached and isinstance(reached.get("arrival_sim_s"), (int, float))
                  else ("" if reached else "  (not reached)"))
        _label(draw, (zx - r, zy + r + 3), label, colour, small, limit=map_img.width)

    for survivor in summary.get("survivors", []):
        if not isinstance(survivor.get("x"), (int, float)):
            continue
        sx, sy = to_px(survivor["x"], survivor["y"])
        colour = _COLOURS["survivor"]
        draw.polygon(_star(sx, sy, 10), fill=colour if survivor.get("acknowledged") else None,
                     outline=colour)
        tag = survivor["id"] + ("" if survivor.get("acknowledged") else " (not ack.)")
        _label(draw, (sx + 12, sy - 18), tag, colour, small, limit=map_img.width)

    title = (f"{summary.get('tree', '')}: {summary.get('outcome', '')}  |  "
             f"{len(visited)}/{len(summary.get('zones_planned', []))} zones, "
             f"{sum(1 for s in summary.get('survivors', []) if s.get('acknowledged'))} "
             f"survivors reported, path {summary.get('path_length_m', 0):.1f} m")
    draw.text((10, 12), title, fill=_COLOURS["text"], font=big)
    _legend(draw, map_img.width + 14, _MARGIN_TOP + 6, summary, font=normal, small=small)
    out.parent.mkdir(parents=True, exist_ok=True)
    img.save(out, "PNG")
    return out


def _legend(draw: Any, x: int, y: int, summary: dict[str, Any], *, font: Any,
            small: Any) -> None:
    """Draw the legend and the mission's numbers in the right-hand panel."""
    c = _COLOURS
    draw.text((x, y), "Legend", fill=c["text"], font=font)
    y += 26
    rows: list[tuple[str, Any]] = [
        ("wall / debris", lambda yy: draw.rectangle((x, yy, x + 18, yy + 12),
                                                   fill=c["occupied"])),
        ("robot path", lambda yy: draw.line((x, yy + 6, x + 18, yy + 6), fill=c["path"],
                                            width=3)),
        ("start (hollow), end", lambda yy: (
            draw.ellipse((x, yy + 1, x + 10, yy + 11), outline=c["start"], width=2),
            draw.ellipse((x + 12, yy + 2, x + 20, yy + 10), fill=c["path"]))),
        ("zone reached (n = order)", lambda yy: draw.ellipse((x, yy, x + 14, yy + 14),
                                                            outline=c["zone_visited"],
                                                            width=3)),
        ("zone not reached", lambda yy: draw.ellipse((x, yy, x + 14, yy + 14),
                                                    outline=c["zone_skipped"], width=3)),
        ("base station", lambda yy: draw.rectangle((x, yy, x + 14, yy + 14),
                                                  outline=c["base"], width=3)),
        ("survivor (filled: ack.)", lambda yy: draw.polygon(
            _star(x + 8, yy + 7, 8), fill=c["survivor"])),
    ]
    for text, icon in rows:
        icon(y)
        draw.text((x + 28, y), text, fill=c["text"], font=small)
        y += 24
    y += 10
    sim = summary.get("sim_duration_s")
    lines = [
        f"outcome: {summary.get('outcome')}",
        f"simulated: {sim:.1f} s" if isinstance(sim, (int, float)) else "simulated: -",
        f"wall: {summary.get('wall_duration_s', 0):.1f} s",
        f"ticks: {summary.get('ticks', 0)}",
        f"goals sent: {summary.get('navigation_goals', 0)}",
        f"path: {summary.get('path_length_m', 0):.2f} m",
    ]
    for survivor in summary.get("survivors", []):
        if isinstance(survivor.get("x"), (int, float)):
            lines.append(f"{survivor['id']}: ({survivor['x']:.2f}, {survivor['y']:.2f})")
    for line in lines:
        draw.text((x, y), line, fill=c["text"], font=small)
        y += 19


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
    trace = _read_jsonl(folder / "trace.jsonl")
    written.append(draw_map(summary, trace, folder / "mission.png", inputs.map_yaml))
    if inputs.spec is not None:
        from sar_framework.engine.render import render_to_file

        statuses = summary.get("node_statuses") or {}
        written.append(render_to_file(inputs.spec, folder / "tree.svg", statuses=statuses))
    return written
