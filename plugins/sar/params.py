"""The search-and-rescue app's parameters: the zones, their order and the base station.

The parameter file (``config/mission_params.yaml``) holds the zones as data::

    /**:
      ros__parameters:
        zone_order: ["zone_a", "zone_b"]
        zones:
          zone_a: {x: -3.0, y: 3.0, yaw: 0.0}
          zone_b: {x: 3.5, y: 3.0, yaw: 1.57}
        base_station: {x: 0.0, y: 0.0, yaw: 0.0}
        tick_rate_hz: 2.0

:data:`MISSION_PARAMETERS` is the table (checked with the runner's own before a run),
:func:`mission_problems` the whole-file checks, :func:`read_mission_params` the reading on the
runner's node (a :class:`ZoneManager`). Every problem names the file and key, e.g.
``config/mission_params.yaml: zones.zone_e.x: missing (zone_e is in zone_order)``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from sar_plugins.sar.zone_manager import ZoneManager

from sar_framework.engine.diagnostics import did_you_mean
from sar_framework.engine.param import REQUIRED, Param
from sar_framework.mission.params import ParamReader, declare_default
from sar_framework.mission.params_check import located
from sar_framework.mission.params_file import KeyLocation, ParamsError
from sar_framework.mission.runner_params import TICK_RATE_HZ, pose_params

if TYPE_CHECKING:
    from rclpy.node import Node

MISSION_PARAMETERS: tuple[Param, ...] = (
    Param("zone_order", list[str], REQUIRED, "the zone ids to visit, in order"),
    *pose_params("zones.*", "a zone", REQUIRED),
    *pose_params("base_station", "base station", 0.0),
)
"""The app's parameters, read by the runner for a tree that uses the app."""
_POSE_KEYS = ("x", "y", "yaw")


@dataclass(frozen=True)
class MissionParams:
    """The mission as the parameters describe it.

    Attributes:
        zone_manager: A fresh ZoneManager over ``zone_order``.
        tick_rate_hz: How often the tree ticks (> 0).
        zone_order: The zone ids in visiting order.
        unused_zones: Zones defined under ``zones`` but not in ``zone_order`` (never visited).
    """

    zone_manager: ZoneManager
    tick_rate_hz: float
    zone_order: tuple[str, ...]
    unused_zones: tuple[str, ...] = ()


class _Reader(ParamReader):
    """Reads the mission's typed values from a node."""

    def raw(self, key: str) -> Any:
        from rclpy.parameter import Parameter

        if not self._node.has_parameter(key):
            return None
        parameter = self._node.get_parameter(key)
        return None if parameter.type_ == Parameter.Type.NOT_SET else parameter.value

    def number(self, key: str, missing: str) -> float:
        value = self.raw(key)
        if value is None:
            raise self.error(key, missing)
        return self.finite_number(key, value)

    def zone_order(self) -> list[str]:
        value = self.raw("zone_order")
        if value is None:
            raise self.error("zone_order", "missing (list the zone ids to visit, in order)")
        if isinstance(value, str) or not all(isinstance(v, str) for v in value):
            raise self.error("zone_order", f"must be a list of zone ids (strings), got {value!r}")
        order = list(value)
        if not order:
            raise self.error("zone_order", "empty (list at least one zone id)")
        seen: set[str] = set()
        for index, zone_id in enumerate(order):
            if not zone_id:
                raise self.error("zone_order", f"entry {index} is an empty zone id")
            if zone_id in seen:
                raise self.error("zone_order", f"{zone_id} is listed twice")
            seen.add(zone_id)
        return order


def read_mission_params(node: Node, *, source: str = "mission parameters",
                        locations: Mapping[str, KeyLocation] | None = None) -> MissionParams:
    """Read ``zone_order``, ``zones.*``, ``base_station.*`` and ``tick_rate_hz``.

    Args:
        node: A node made by :func:`create_params_node` (or one with the same flags).
        source: How to name where the parameters came from when a key's file is unknown
            (usually the parameter file's path).
        locations: Where each key is set (from
            :func:`sar_framework.mission.params_file.check_params_file`); adds line numbers.

    Returns:
        The mission parameters.

    Raises:
        ParamsError: The first problem found, naming the file and key.
    """
    reader = _Reader(node, source, locations or {})
    for param in (TICK_RATE_HZ, *MISSION_PARAMETERS):  # the defaults, from the tables
        if param.name == TICK_RATE_HZ.name or param.name.startswith("base_station."):
            declare_default(node, param.name, param.default)

    order = reader.zone_order()
    zones = []
    for zone_id in order:
        zone: dict[str, Any] = {"id": zone_id}
        for key in _POSE_KEYS:
            zone[key] = reader.number(f"zones.{zone_id}.{key}",
                                      f"missing ({zone_id} is in zone_order)")
        zones.append(zone)
    base = {key: reader.number(f"base_station.{key}", "missing") for key in _POSE_KEYS}
    tick_rate_hz = reader.number("tick_rate_hz", "missing")
    problem = TICK_RATE_HZ.problem(reader.raw("tick_rate_hz"))
    if problem is not None:
        raise reader.error("tick_rate_hz", problem)

    listed = node.list_parameters(["zones"], 0).names  # depth 0: recursive
    defined = {name.split(".")[1] for name in listed if name.count(".") >= 2}
    unused = tuple(sorted(defined - set(order)))
    try:
        manager = ZoneManager(zones, base)
    except ValueError as err:  # already checked above; kept so nothing escapes unworded
        raise ParamsError(source, "zones", str(err)) from None
    return MissionParams(manager, tick_rate_hz, tuple(order), unused)


def mission_problems(values: Mapping[str, Any], where: Mapping[str, KeyLocation],
                     source: str) -> list[ParamsError]:
    """What the runner would reject about the mission itself (zones and their order).

    Args:
        values: The runner's parameters (file values, then overrides).
        where: Where each name is set.
        source: Names the parameter file.

    Returns:
        Every problem: ``zone_order`` missing, empty, repeated or naming a zone without
        coordinates.
    """
    order = values.get("zone_order")
    if order is None:
        return [ParamsError(source, "zone_order", "missing (list the zone ids to visit, "
                            "in order)")]
    if not isinstance(order, list) or not all(isinstance(z, str) for z in order):
        return []  # the type check said so
    problems = []
    seen: set[str] = set()
    for zone_id in order:
        if not zone_id:
            problems.append(located("zone_order", "an empty zone id", where, source))
        elif zone_id in seen:
            problems.append(located("zone_order", f"{zone_id} is listed twice", where, source))
        seen.add(zone_id)
        for axis in ("x", "y", "yaw"):
            if zone_id and f"zones.{zone_id}.{axis}" not in values:
                defined = sorted({k.split(".")[1] for k in values if k.startswith("zones.")})
                problems.append(located(
                    "zone_order", f"zones.{zone_id}.{axis} is missing ({zone_id} is in "
                    "zone_order)" + did_you_mean(zone_id, defined), where, source))
                break
    return problems


def zone_positions(values: Mapping[str, Any]) -> dict[str, tuple[float, float]]:
    """Zone id -> ``(x, y)`` for every zone with both coordinates set as numbers."""
    zones: dict[str, tuple[float, float]] = {}
    for name, value in values.items():
        parts = name.split(".")
        if len(parts) == 3 and parts[0] == "zones" and parts[2] == "x":
            y = values.get(f"zones.{parts[1]}.y")
            if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in (value, y)):
                zones[parts[1]] = (float(value), float(y))
    return zones
