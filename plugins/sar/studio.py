"""The search-and-rescue app in the studio and ``sar-tree watch``: zones, survivors, the zone.

- :func:`layout`: the zones in visiting order and the base station (the world view);
- :data:`MARKS`: which of its events mark the timeline;
- :func:`frame`: the zones reached and the survivors found so far;
- :func:`status_text`: the zone the mission is at (``zone zone_b (2/4)``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from sar_plugins.sar.events import SarKind
from sar_plugins.sar.report import mission_layout

from sar_framework.events.event import MissionEvent

MARKS = {SarKind.ZONE_REACHED.value: "reached", SarKind.ZONE_UNREACHED.value: "failure",
         SarKind.SURVIVOR_BROADCAST.value: "found", SarKind.DETECTION.value: "found"}
"""The timeline's marks of the app's events."""
_FOUND_KINDS = frozenset({SarKind.SURVIVOR_BROADCAST, SarKind.DETECTION})


def layout(params_file: str) -> dict[str, Any]:
    """The zones (the places, in visiting order) and the base station of a parameter file."""
    zones, base = mission_layout(params_file)
    return {"places": zones, "base": base}


def frame(events: Sequence[MissionEvent]) -> dict[str, Any]:
    """The zones reached and the survivors found (one per position, named once broadcast)."""
    found: dict[tuple[float, ...], str] = {}
    for event in events:
        if event.kind in _FOUND_KINDS and event.position is not None:
            key = tuple(round(v, 2) for v in event.position)
            found[key] = event.value("survivor_id") or found.get(key, "")
    return {"reached": [e.value("zone_id") for e in events if e.kind == SarKind.ZONE_REACHED],
            "found": [{"id": name, "position": list(key)} for key, name in found.items()]}


def status_text(document: Mapping[str, Any]) -> str:
    """``zone zone_b (2/4)``, ``zone none left`` once every zone is done, "" without it."""
    if "zone" not in document:
        return ""
    zone = document["zone"]
    where = f"{zone['id']} ({zone['index'] + 1}/{zone['total']})" if zone else "none left"
    return "zone " + where
