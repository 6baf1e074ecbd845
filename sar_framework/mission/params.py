"""Mission parameters from a ROS node -> a ZoneManager and a tick rate.

The parameter file (``config/mission_params.yaml``) holds the zones as data::

    /**:
      ros__parameters:
        zone_order: ["zone_a", "zone_b"]
        zones:
          zone_a: {x: -3.0, y: 3.0, yaw: 0.0}
          zone_b: {x: 3.5, y: 3.0, yaw: 1.57}
        base_station: {x: 0.0, y: 0.0, yaw: 0.0}
        tick_rate_hz: 2.0

The reading node is created with ``automatically_declare_parameters_from_overrides=True``
and ``allow_undeclared_parameters=True`` (see :func:`create_params_node`), so every key of
the file is declared by rclpy; a default is declared only where the file did not set the
key (:func:`declare_default`), which avoids ``ParameterAlreadyDeclaredException``.

Every problem is one :class:`ParamsError` naming the file and key, e.g.
``config/mission_params.yaml: zones.zone_e.x: missing (zone_e is in zone_order)``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from sar_framework.mission.params_file import KeyLocation, ParamsError
from sar_framework.mission.runner_params import MISSION_PARAMETERS, TICK_RATE_HZ
from sar_framework.mission.zone_manager import ZoneManager

if TYPE_CHECKING:
    from rclpy.node import Node

__all__ = [
    "DEFAULT_TICK_RATE_HZ",
    "MissionParams",
    "ParamReader",
    "ParamsError",
    "create_params_node",
    "declare_default",
    "read_mission_params",
]

#: Tick rate when the parameter file does not set ``tick_rate_hz`` (from the runner's table).
DEFAULT_TICK_RATE_HZ: float = TICK_RATE_HZ.default
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


def create_params_node(name: str, **kwargs: Any) -> Node:
    """Create a node that declares every parameter given in its parameter files.

    Args:
        name: The node name.
        **kwargs: Further ``rclpy.node.Node`` arguments (``context``, ``namespace``...).

    Returns:
        The node.
    """
    from rclpy.node import Node

    return Node(name, automatically_declare_parameters_from_overrides=True,
                allow_undeclared_parameters=True, **kwargs)


def declare_default(node: Node, name: str, value: Any) -> Any:
    """Declare ``name`` with ``value`` unless it is already declared; return its value.

    Args:
        node: The parameter-reading node.
        name: The parameter name.
        value: The default, used only when no parameter file or override set it.

    Returns:
        The parameter's current value.
    """
    if not node.has_parameter(name):
        node.declare_parameter(name, value)
    return node.get_parameter(name).value


class ParamReader:
    """Base of the parameter readers: a node, and errors worded with file, key and line.

    Args:
        node: The parameter-reading node.
        source: Names where parameters came from when a key's file is unknown.
        locations: Where each key is set in the parameter files (adds line numbers).
    """

    def __init__(self, node: Node, source: str, locations: Mapping[str, KeyLocation]) -> None:
        self._node = node
        self._source = source
        self._locations = locations

    def error(self, key: str, problem: str) -> ParamsError:
        """Return the error for ``key``, at its file and line when known.

        Args:
            key: The parameter name.
            problem: What is wrong with it.

        Returns:
            The error (to raise).
        """
        where = self._locations.get(key)
        if where is None:
            return ParamsError(self._source, key, problem)
        return ParamsError(where.file, key, problem, where.line)

    def finite_number(self, key: str, value: Any) -> float:
        """Return ``value`` as a float if it is a finite number (not a bool).

        Args:
            key: The parameter name, for the error.
            value: The parameter's value.

        Returns:
            The number.

        Raises:
            ParamsError: ``value`` is not a number, or not finite.
        """
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self.error(key, f"must be a number, got {value!r}")
        if not math.isfinite(value):
            raise self.error(key, f"must be finite, got {value!r}")
        return float(value)


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
