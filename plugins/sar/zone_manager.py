"""ZoneManager: the ordered list of zones a mission visits, plus the base station.

Every leaf that needs zone state receives the same instance by constructor injection
(the mission tree has no blackboard). The class is plain Python so it can be tested
and reused without ROS::

    zm = ZoneManager([{"id": "zone_a", "x": -3.0, "y": 3.0, "yaw": 0.0}],
                     {"x": 0.0, "y": 0.0, "yaw": 0.0})
    while zm.has_remaining():
        goal = zm.current_zone()   # {"id": "zone_a", "x": -3.0, "y": 3.0, "yaw": 0.0}
        zm.advance()
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from typing import Any

from sar_plugins.sar.events import SarKind

from sar_framework.events.event import EventKind

ZoneListener = Callable[[EventKind, dict[str, Any]], None]
"""Told ``(ZONE_REACHED or ZONE_UNREACHED, zone)`` as the mission walks its zones."""

_POSE_KEYS = ("x", "y", "yaw")


def _number(value: Any, where: str, key: str) -> float:
    """Return ``value`` as a finite float or raise ValueError naming ``where`` and ``key``."""
    # bool is an int subclass; ``x: true`` in a parameter file is a mistake, not 1.0.
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"{where}: key '{key}' must be a number, got {value!r}")
    number = float(value)
    if not math.isfinite(number):
        raise ValueError(f"{where}: key '{key}' must be finite, got {value!r}")
    return number


def _pose(entry: Any, where: str) -> dict[str, float]:
    """Validate a mapping with numeric ``x``, ``y`` and ``yaw`` and return it as floats."""
    if not isinstance(entry, Mapping):
        raise ValueError(f"{where}: expected a mapping with keys x, y, yaw, got {entry!r}")
    pose = {}
    for key in _POSE_KEYS:
        if key not in entry:
            raise ValueError(f"{where}: missing key '{key}'")
        pose[key] = _number(entry[key], where, key)
    return pose


class ZoneManager:
    """Walks a mission through its zones in order and allocates survivor ids.

    Args:
        zones: The zones in visiting order; each a mapping with ``id`` (non-empty str)
            and numeric, finite ``x``, ``y`` (metres, frame ``map``) and ``yaw`` (radians).
            Ids must be unique. An empty list is allowed (the mission just returns to base).
        base_station: A mapping with numeric, finite ``x``, ``y`` and ``yaw``.

    Raises:
        ValueError: If a zone or the base station is malformed; the message names the
            zone (by index and id when known) and the offending key.
    """

    def __init__(self, zones: Sequence[Mapping[str, Any]], base_station: Mapping[str, Any]) -> None:
        if isinstance(zones, (str, bytes)) or not isinstance(zones, Sequence):
            raise ValueError(f"zones: expected a list of zone mappings, got {zones!r}")
        self._zones: list[dict[str, Any]] = []
        seen: dict[str, int] = {}
        for index, zone in enumerate(zones):
            where = f"zones[{index}]"
            if not isinstance(zone, Mapping):
                raise ValueError(f"{where}: expected a mapping with keys id, x, y, yaw")
            zone_id = zone.get("id")
            if not isinstance(zone_id, str) or not zone_id:
                raise ValueError(f"{where}: key 'id' must be a non-empty string, got {zone_id!r}")
            where = f"zones[{index}] ({zone_id!r})"
            if zone_id in seen:
                raise ValueError(
                    f"{where}: key 'id' duplicates zones[{seen[zone_id]}]; zone ids must be unique"
                )
            seen[zone_id] = index
            self._zones.append({"id": zone_id, **_pose(zone, where)})
        self._base = _pose(base_station, "base_station")
        self._index = 0
        self._survivors = 0
        self._reached: set[str] = set()
        self._listeners: list[ZoneListener] = []

    def observe(self, listener: ZoneListener) -> None:
        """Tell ``listener`` when a zone is reached, and when one is passed unreached.

        Args:
            listener: Called with ``(SarKind.ZONE_REACHED, zone)`` from
                :meth:`mark_reached` and ``(SarKind.ZONE_UNREACHED, zone)`` from
                :meth:`advance` past a zone never reached (``zone`` a copy).
        """
        self._listeners.append(listener)

    def _tell(self, kind: EventKind, zone: dict[str, Any]) -> None:
        for listener in self._listeners:
            listener(kind, dict(zone))

    def current_zone(self) -> dict[str, Any]:
        """Return the zone to visit now.

        Returns:
            A fresh dict ``{"id", "x", "y", "yaw"}``; changing it does not change the manager.

        Raises:
            IndexError: If every zone has been visited (check :meth:`has_remaining` first).
        """
        if self._index >= len(self._zones):
            raise IndexError(
                f"no current zone: all {len(self._zones)} zones have been visited "
                "(check has_remaining() before current_zone())"
            )
        return dict(self._zones[self._index])

    def has_remaining(self) -> bool:
        """Return True while there is a zone left to visit."""
        return self._index < len(self._zones)

    def advance(self) -> None:
        """Move on to the next zone; does nothing once every zone has been visited."""
        if self._index < len(self._zones):
            zone = self._zones[self._index]
            self._index += 1
            if zone["id"] not in self._reached:
                self._tell(SarKind.ZONE_UNREACHED, zone)

    def mark_reached(self, zone_id: str) -> None:
        """Record that the robot reached ``zone_id`` (NavigateToZone calls it on success)."""
        self._reached.add(zone_id)
        zone = next((z for z in self._zones if z["id"] == zone_id), {"id": zone_id})
        self._tell(SarKind.ZONE_REACHED, zone)

    def zone(self, zone_id: str) -> dict[str, Any]:
        """Return a copy of zone ``zone_id`` (``{"id", "x", "y", "yaw"}``).

        Raises:
            KeyError: ``zone_id`` is not a zone of the mission.
        """
        found = next((z for z in self._zones if z["id"] == zone_id), None)
        if found is None:
            known = ", ".join(z["id"] for z in self._zones)
            raise KeyError(f"{zone_id!r} is not a zone of the mission (zones: {known})")
        return dict(found)

    def claim(self, zone_id: str) -> None:
        """Make ``zone_id`` the current zone (a fleet's ``ClaimZone`` won it in an auction).

        The zone moves to the current position, so :meth:`current_zone` returns it and
        :meth:`advance` moves past it; the other zones keep their order. A zone already
        passed may be claimed again (it was given back by another robot, or reopened).

        Args:
            zone_id: One of the mission's zones.

        Raises:
            KeyError: ``zone_id`` is not a zone of the mission.
        """
        position = next((i for i, z in enumerate(self._zones) if z["id"] == zone_id), None)
        if position is None:
            known = ", ".join(z["id"] for z in self._zones)
            raise KeyError(f"claim({zone_id!r}): not a zone of the mission (zones: {known})")
        zone = self._zones.pop(position)
        if position < self._index:
            self._index -= 1
        self._zones.insert(self._index, zone)

    def skipped_zones(self) -> list[str]:
        """The zones already passed (advanced over) that were never reached, in order."""
        return [z["id"] for z in self._zones[:self._index] if z["id"] not in self._reached]

    def base_pose(self) -> dict[str, float]:
        """Return a copy of the base station pose ``{"x", "y", "yaw"}``."""
        return dict(self._base)

    def next_survivor_id(self) -> str:
        """Allocate the next survivor frame id: ``"survivor_1"``, ``"survivor_2"``, ...

        Each call allocates a new id, so call it once per detection.
        """
        self._survivors += 1
        return f"survivor_{self._survivors}"

    def current_index(self) -> int:
        """Return the 0-based index of the current zone (equals :meth:`total_zones` when done)."""
        return self._index

    def total_zones(self) -> int:
        """Return the number of zones in the mission."""
        return len(self._zones)

    def __repr__(self) -> str:
        return f"ZoneManager(index={self._index}, zones={[z['id'] for z in self._zones]!r})"
