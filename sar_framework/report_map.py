"""``mission.png``: the run's map with the robot's path, its goals and blocked areas.

Plain Python (numpy, Pillow; no ROS). :func:`draw_map` draws a ``mission.json`` document
(:func:`sar_framework.report.summarise`) and the simulator's trace: the occupancy map the
simulator ran on (the trace's ``start`` names it; any map_server map), injected blocked
areas and the robot's path, then what each app draws (:class:`MapLayer`), or the navigation
goals when no app drew, with a title (the tree path cut at the left when long) and a legend.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from sar_framework.sim.params import DEFAULT_MAP_YAML

MAP_YAML = DEFAULT_MAP_YAML
"""The map drawn when the trace names none (the simulator's default map)."""


_SCALE = 3  # pixels per map cell (0.05 m -> 60 px per metre)
_MARGIN_TOP = 44
_LEGEND_W = 250
_COLOURS = {
    "free": (250, 250, 247), "occupied": (55, 60, 68), "unknown": (205, 205, 205),
    "path": (30, 110, 220), "start": (30, 110, 220),
    "text": (25, 25, 25), "panel": (255, 255, 255), "grid": (232, 232, 228),
    "blocked": (150, 20, 120), "goal_reached": (46, 160, 67), "goal_missed": (220, 60, 50),
}
BLOCKED_COLOUR = _COLOURS["blocked"]
"""The colour of injected blocked areas on ``mission.png``."""


def star(cx: float, cy: float, radius: float) -> list[tuple[float, float]]:
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


def fit_left(text: str, room: float, measure: Callable[[str], float]) -> str:
    """``text`` cut at the left (behind an ellipsis) until ``measure`` says it fits ``room``.

    Args:
        text: E.g. an absolute tree path; its end (the file name) matters most.
        room: The width available (px).
        measure: The drawn width of a text (px).
    """
    if measure(text) <= room:
        return text
    for start in range(1, len(text)):
        candidate = "…" + text[start:]
        if measure(candidate) <= room:
            return candidate
    return "…"


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


def font(size: int) -> Any:
    """Pillow's default font at ``size`` (a fixed bitmap font before Pillow 10.1)."""
    return _font(size)


def label(draw: Any, xy: tuple[float, float], text: str, colour: Any, font: Any, *,
          limit: float) -> None:
    """Draw ``text`` on a white box, moved left to end before ``limit`` (the legend)."""
    _label(draw, xy, text, colour, font, limit=limit)


def _font(size: int) -> Any:
    from PIL import ImageFont

    try:
        return ImageFont.load_default(size=size)
    except TypeError:  # Pillow < 10.1: a fixed bitmap font
        return ImageFont.load_default()


@dataclass
class MapCanvas:
    """The course map drawn at :data:`_SCALE`, a title strip above, a legend panel right.

    Attributes:
        img: The whole picture (``PIL.Image``).
        draw: Its ``ImageDraw``.
        map_img: The map alone (its width is where the legend panel starts).
        px_per_m: Pixels per metre.
        to_px: Map ``(x, y)`` metres -> picture ``(col, row)`` pixels.
    """

    img: Any
    draw: Any
    map_img: Any
    px_per_m: float
    to_px: Callable[[float, float], tuple[float, float]]


def map_canvas(map_yaml: Path = MAP_YAML, legend_w: int = _LEGEND_W) -> MapCanvas:
    """The occupancy map (walls and debris) on a white picture with a 1 m dotted grid.

    Args:
        map_yaml: The occupancy map.
        legend_w: The legend panel's width, pixels.
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
    width = map_img.width + legend_w
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
    return MapCanvas(img, draw, map_img, px_per_m, to_px)


@dataclass
class MapLayer:
    """What an app drew on ``mission.png`` and adds to its title and legend.

    Attributes:
        title: Its facts in the title (``3/3 shelves scanned``).
        legend: ``(text, icon)`` rows; ``icon(draw, x, y)`` draws a row's symbol.
        lines: Its lines in the panel, after the run's numbers.
    """

    title: str = ""
    legend: list[tuple[str, Callable[[Any, int, int], Any]]] = field(default_factory=list)
    lines: list[str] = field(default_factory=list)


def _goal_layer(canvas: MapCanvas, summary: dict[str, Any]) -> MapLayer:
    """The navigation goals: a green diamond where one was reached, a red cross elsewhere."""
    draw, to_px, small = canvas.draw, canvas.to_px, _font(13)
    goals = summary.get("goals", [])
    for goal in goals:
        gx, gy = to_px(goal["x"], goal["y"])
        if goal.get("result") == "reached":
            colour = _COLOURS["goal_reached"]
            draw.polygon(diamond(gx, gy, 9), outline=colour, width=3)
        else:
            colour = _COLOURS["goal_missed"]
            draw.line((gx - 8, gy - 8, gx + 8, gy + 8), fill=colour, width=3)
            draw.line((gx - 8, gy + 8, gx + 8, gy - 8), fill=colour, width=3)
        _label(draw, (gx + 11, gy + 4), goal.get("node") or "goal", colour, small,
               limit=canvas.map_img.width)
    reached = sum(1 for g in goals if g.get("result") == "reached")
    return MapLayer(
        title=f"{reached}/{len(goals)} goals reached",
        legend=[("goal reached", lambda d, x, y: d.polygon(
                    diamond(x + 8, y + 7, 7), outline=_COLOURS["goal_reached"], width=3)),
                ("goal not reached", lambda d, x, y: (
                    d.line((x + 2, y + 1, x + 14, y + 13), fill=_COLOURS["goal_missed"], width=3),
                    d.line((x + 2, y + 13, x + 14, y + 1), fill=_COLOURS["goal_missed"],
                           width=3)))])


def diamond(cx: float, cy: float, radius: float) -> list[tuple[float, float]]:
    """The four corners of a diamond centred on ``(cx, cy)``."""
    return [(cx, cy - radius), (cx + radius, cy), (cx, cy + radius), (cx - radius, cy)]


def trace_map(trace: Sequence[dict[str, Any]]) -> Path | None:
    """The map the simulator ran on, as its trace's ``start`` record names it (None: none)."""
    start = next((r for r in trace if r.get("event") == "start"), None)
    named = start.get("map") if start is not None else None
    return Path(named) if isinstance(named, str) and named else None


def draw_map(summary: dict[str, Any], trace: Sequence[dict[str, Any]], out: Path,
             map_yaml: Path | None = None, apps: Sequence[Any] | None = None) -> Path:
    """Draw ``mission.png``: map, path, blocked areas, what the apps show, title and legend.

    Each app with a ``figure`` hook draws its part; when none drew anything, the navigation
    goals are drawn.

    Args:
        summary: The ``mission.json`` document.
        trace: The simulator's trace records (poses are drawn as the path).
        out: The PNG file to write.
        map_yaml: The occupancy map; None: the one the trace names, else :data:`MAP_YAML`.
        apps: The apps whose parts to draw; None: every installed app (each draws only
            what ``summary`` holds of it).

    Returns:
        ``out``.
    """
    from sar_framework.app import discover_apps

    canvas = map_canvas(map_yaml or trace_map(trace) or MAP_YAML)
    img, draw, to_px, px_per_m = canvas.img, canvas.draw, canvas.to_px, canvas.px_per_m
    width = img.width
    normal, big, small = _font(15), _font(18), _font(13)

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

    for area in summary.get("blocked_areas", []):
        ax, ay = to_px(area["x"], area["y"])
        r = area["radius"] * px_per_m
        draw.ellipse((ax - r, ay - r, ax + r, ay + r), outline=_COLOURS["blocked"], width=3)
        draw.line((ax - r * 0.7, ay - r * 0.7, ax + r * 0.7, ay + r * 0.7),
                  fill=_COLOURS["blocked"], width=3)

    layers = [layer for app in (discover_apps() if apps is None else apps)
              if getattr(app, "figure", None) is not None
              for layer in [app.figure(canvas, summary)] if layer is not None]
    if not layers:
        layers = [_goal_layer(canvas, summary)]
    titles = ", ".join(layer.title for layer in layers if layer.title)
    facts = (f": {summary.get('outcome', '')}  |  {titles + ', ' if titles else ''}"
             f"path {summary.get('path_length_m', 0):.1f} m")
    tree = fit_left(str(summary.get("tree", "")), width - 20 - draw.textlength(facts, font=big),
                    lambda text: draw.textlength(text, font=big))
    draw.text((10, 12), tree + facts, fill=_COLOURS["text"], font=big)
    _legend(draw, canvas.map_img.width + 14, _MARGIN_TOP + 6, summary, layers, font=normal,
            small=small)
    out.parent.mkdir(parents=True, exist_ok=True)
    img.save(out, "PNG")
    return out


def _legend(draw: Any, x: int, y: int, summary: dict[str, Any], layers: Sequence[MapLayer],
            *, font: Any, small: Any) -> None:
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
    ]
    for layer in layers:
        rows += [(text, lambda yy, icon=icon: icon(draw, x, yy)) for text, icon in layer.legend]
    if summary.get("blocked_areas"):
        rows.append(("blocked area (fault)", lambda yy: draw.ellipse(
            (x, yy, x + 14, yy + 14), outline=c["blocked"], width=3)))
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
    final = summary.get("final_position")
    if final:
        where = ""
        if "at_base" in summary:
            where = ", at base" if summary["at_base"] else ", not at base"
        lines.append(f"end: ({final['x']:.2f}, {final['y']:.2f}){where}")
    for layer in layers:
        lines += layer.lines
    for line in lines:
        draw.text((x, y), line, fill=c["text"], font=small)
        y += 19
