"""The search-and-rescue app's part of ``mission.png``: base station, zones and survivors.

The planned zones are numbered in visiting order (green once reached, with the arrival
time; red when not), the base station is a square and each survivor a star (filled once
the base acknowledged it), over the core's map and path (:mod:`sar_framework.report_map`).
"""

from __future__ import annotations

from typing import Any

from sar_framework.report_map import MapCanvas, MapLayer, font, label, star

COLOURS = {"zone_visited": (46, 160, 67), "zone_skipped": (220, 60, 50),
           "base": (120, 70, 200), "survivor": (230, 120, 0)}
"""The app's colours on the map."""


def mission_figure(canvas: MapCanvas, summary: dict[str, Any]) -> MapLayer | None:
    """Draw the base, the zones and the survivors; None when ``summary`` has no zones."""
    if "zones_planned" not in summary:
        return None
    draw, to_px, px_per_m, limit = canvas.draw, canvas.to_px, canvas.px_per_m, \
        canvas.map_img.width
    small, normal = font(13), font(15)
    base = summary.get("base_station") or {}
    if "x" in base and "y" in base:
        bx, by = to_px(base["x"], base["y"])
        draw.rectangle((bx - 11, by - 11, bx + 11, by + 11), outline=COLOURS["base"], width=3)
        label(draw, (bx + 14, by + 4), "base", COLOURS["base"], normal, limit=limit)

    visited = {v["id"]: v for v in summary.get("zones_visited", [])}
    for number, zone in enumerate(summary.get("zones_planned", []), 1):
        zx, zy = to_px(zone["x"], zone["y"])
        reached = visited.get(zone["id"])
        colour = COLOURS["zone_visited"] if reached else COLOURS["zone_skipped"]
        r = 0.3 * px_per_m
        draw.ellipse((zx - r, zy - r, zx + r, zy + r), outline=colour, width=3)
        draw.text((zx, zy), str(number), fill=colour, font=normal, anchor="mm")
        text = zone["id"]
        text += (f"  t={reached['arrival_sim_s']:.0f}s"
                 if reached and isinstance(reached.get("arrival_sim_s"), (int, float))
                 else ("" if reached else "  (not reached)"))
        label(draw, (zx - r, zy + r + 3), text, colour, small, limit=limit)

    survivors = summary.get("survivors", [])
    placed = [s for s in survivors if isinstance(s.get("x"), (int, float))]
    for survivor in placed:
        sx, sy = to_px(survivor["x"], survivor["y"])
        colour = COLOURS["survivor"]
        draw.polygon(star(sx, sy, 10), fill=colour if survivor.get("acknowledged") else None,
                     outline=colour)
        tag = survivor["id"] + ("" if survivor.get("acknowledged") else " (not ack.)")
        label(draw, (sx + 12, sy - 18), tag, colour, small, limit=limit)

    reported = sum(1 for s in survivors if s.get("acknowledged"))
    return MapLayer(
        title=f"{len(visited)}/{len(summary.get('zones_planned', []))} zones, "
              f"{reported} survivors reported",
        legend=[
            ("zone reached (n = order)", lambda d, x, y: d.ellipse(
                (x, y, x + 14, y + 14), outline=COLOURS["zone_visited"], width=3)),
            ("zone not reached", lambda d, x, y: d.ellipse(
                (x, y, x + 14, y + 14), outline=COLOURS["zone_skipped"], width=3)),
            ("base station", lambda d, x, y: d.rectangle(
                (x, y, x + 14, y + 14), outline=COLOURS["base"], width=3)),
            ("survivor (filled: ack.)", lambda d, x, y: d.polygon(
                star(x + 8, y + 7, 8), fill=COLOURS["survivor"])),
        ],
        lines=[f"{s['id']}: ({s['x']:.2f}, {s['y']:.2f})" for s in placed])
