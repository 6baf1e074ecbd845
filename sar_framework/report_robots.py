"""The report of a run of named robots: ``fleet.json`` and ``fleet.png`` beside theirs.

Each robot's report is the one any run writes (:mod:`sar_framework.report`), in its folder
(``RUN/<name>/``). This adds the run's own page, plain Python (Pillow; no ROS):

- ``fleet.json``: the run's verdict (:func:`~sar_framework.orchestrate.outcome.robots_outcome`:
  every robot's, and the problems the tree's apps find across the robots), its times, and
  per robot its verdict, final position, simulated time, path length and report; each app
  adds its keys (:attr:`sar_framework.app.App.fleet_report`);
- ``fleet.png``: each robot's path from its own trace (``RUN/<name>/trace.jsonl``) in its
  own colour, its spawn (hollow) and end (filled), a line per robot in the panel, and what
  the apps draw (:attr:`sar_framework.app.App.fleet_figure`).
"""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from sar_framework.app import App
from sar_framework.events.jsonl import read_json_lines
from sar_framework.mission.processes import MissionSettings
from sar_framework.report_map import MAP_YAML, MapLayer, font, map_canvas, trace_map

ROBOT_COLOURS = ((30, 110, 220), (220, 90, 30), (40, 150, 60), (150, 60, 190),
                 (200, 40, 110), (0, 150, 160), (140, 110, 20), (90, 90, 90))
"""One colour per robot, in the run's order (repeats after eight)."""
FLEET_JSON = "fleet.json"
FLEET_PNG = "fleet.png"
_TEXT = (25, 25, 25)
_LEGEND_W = 420


def app_findings(settings: MissionSettings, summaries: Mapping[str, dict[str, Any]],
                 apps: Sequence[App]) -> tuple[dict[str, Any], list[str]]:
    """The apps' keys of ``fleet.json`` and the problems they find across the robots."""
    keys: dict[str, Any] = {}
    problems: list[str] = []
    for app in apps:
        if app.fleet_report is None:
            continue
        own, found = app.fleet_report(settings, summaries)
        for name, entry in own.pop("robots", {}).items():
            keys.setdefault("robots", {}).setdefault(name, {}).update(entry)
        keys.update(own)
        problems += found
    return keys, problems


def fleet_document(status: str, reason: str, robots: Mapping[str, Any],
                   summaries: Mapping[str, dict[str, Any]], app_keys: dict[str, Any], *,
                   wall_duration_s: float) -> dict[str, Any]:
    """``fleet.json``: the run's verdict, each robot's, the apps' keys.

    Args:
        status: The run's verdict.
        reason: Why, when it is not SUCCESS.
        robots: Robot name -> its verdict (an ``Outcome``: ``status``, ``reason``).
        summaries: Robot name -> its ``mission.json``.
        app_keys: :func:`app_findings`' keys.
        wall_duration_s: Wall seconds of the whole run.
    """
    sims = [s.get("sim_duration_s") for s in summaries.values()]
    own = app_keys.get("robots", {})
    return {
        "outcome": status,
        "reason": reason,
        **{k: v for k, v in app_keys.items() if k != "robots"},
        "sim_duration_s": max((t for t in sims if isinstance(t, (int, float))), default=None),
        "wall_duration_s": round(wall_duration_s, 3),
        "robots": {name: {
            "outcome": o.status, "reason": o.reason,
            **own.get(name, {}),
            "final_position": summaries.get(name, {}).get("final_position"),
            "sim_duration_s": summaries.get(name, {}).get("sim_duration_s"),
            "path_length_m": summaries.get(name, {}).get("path_length_m"),
            "report": f"{name}/mission.json"} for name, o in robots.items()},
    }


def write_fleet_json(run_folder: Path, document: dict[str, Any]) -> Path:
    """Write ``fleet.json`` into the run folder."""
    path = run_folder / FLEET_JSON
    path.write_text(json.dumps(document, indent=2) + "\n", encoding="utf-8")
    return path


def _trace_poses(path: Path) -> list[tuple[float, float]]:
    return [(float(record["x"]), float(record["y"])) for record in read_json_lines(path)
            if "x" in record and "y" in record and record.get("event") in (None, "start")]


def draw_fleet(run_folder: Path, document: dict[str, Any], apps: Sequence[App], out: Path,
               *, map_yaml: Path | None = None) -> Path:
    """Draw ``fleet.png``.

    Args:
        run_folder: The run folder (each robot's trace in ``run_folder/<name>/trace.jsonl``).
        document: The ``fleet.json`` document.
        apps: The tree's apps (each draws its part).
        out: The PNG file to write.
        map_yaml: The occupancy map; None: the one the first robot's trace names, else
            :data:`~sar_framework.report_map.MAP_YAML`.

    Returns:
        ``out``.
    """
    first = next(iter(document.get("robots", {})), None)
    traced = (trace_map(read_json_lines(run_folder / first / "trace.jsonl"))
              if first else None)
    canvas = map_canvas(map_yaml or traced or MAP_YAML, _LEGEND_W)
    draw = canvas.draw
    colours = {name: ROBOT_COLOURS[i % len(ROBOT_COLOURS)]
               for i, name in enumerate(document.get("robots", {}))}
    for name, colour in colours.items():
        poses = [canvas.to_px(x, y) for x, y in _trace_poses(run_folder / name / "trace.jsonl")]
        if len(poses) >= 2:
            draw.line(poses, fill=colour, width=3, joint="curve")
        if poses:
            (sx, sy), (ex, ey) = poses[0], poses[-1]
            draw.ellipse((sx - 6, sy - 6, sx + 6, sy + 6), outline=colour, width=2)
            draw.ellipse((ex - 4, ey - 4, ex + 4, ey + 4), fill=colour)
    layers: list[MapLayer] = [layer for app in apps if app.fleet_figure is not None
                              for layer in [app.fleet_figure(canvas, document, run_folder,
                                                             colours)] if layer is not None]
    title = f"Fleet of {len(colours)}: {document.get('outcome', '')}"
    draw.text((10, 12), "  |  ".join([title, *(la.title for la in layers if la.title)]),
              fill=_TEXT, font=font(18))
    _legend(draw, (canvas.map_img.width + 14, 50), document, colours, layers)
    out.parent.mkdir(parents=True, exist_ok=True)
    canvas.img.save(out, "PNG")
    return out


def _legend(draw: Any, xy: tuple[int, int], document: dict[str, Any],
            colours: dict[str, tuple[int, int, int]], layers: Sequence[MapLayer]) -> None:
    """The robots (colour, verdict, time, home when an app says) and the apps' lines."""
    x, y = xy
    normal, small = font(15), font(13)
    draw.text((x, y), "Robots (path; hollow: spawn)", fill=_TEXT, font=normal)
    y += 24
    for name, colour in colours.items():
        robot = document["robots"][name]
        sim = robot.get("sim_duration_s")
        timing = f"{sim:.0f} s" if isinstance(sim, (int, float)) else "-"
        home = ("" if "at_base" not in robot
                else ", home" if robot["at_base"] else ", not home")
        draw.line((x, y + 7, x + 22, y + 7), fill=colour, width=4)
        draw.text((x + 30, y), f"{name}: {robot.get('outcome')}, {timing}{home}",
                  fill=_TEXT, font=small)
        y += 20
    for layer in layers:
        y += 12
        for line in layer.lines:
            draw.text((x, y), line, fill=_TEXT, font=small)
            y += 18
