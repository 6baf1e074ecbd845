"""The simulator's parameters: declared on ``sar_sim``, validated into :class:`SimSettings`.

Integers are accepted where a float is expected (``speed:=20``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from rcl_interfaces.msg import ParameterDescriptor
from rclpy.exceptions import ParameterUninitializedException
from rclpy.node import Node
from rclpy.parameter import Parameter

from sar_framework.sim.drive import DriveLimits
from sar_framework.sim.faults import FaultConfigError, Faults, make_faults
from sar_framework.sim.occupancy import DEFAULT_MAP_PREFIX, MapError, OccupancyGrid, load_map
from sar_framework.sim.world import DEFAULT_WORLD_PATH, Pose2D, World, WorldError, load_world

DEFAULT_MAP_YAML = DEFAULT_MAP_PREFIX.with_name(DEFAULT_MAP_PREFIX.name + ".yaml")
"""The committed course map (``maps/final_project_map.yaml``)."""

class SimConfigError(ValueError):
    """A simulator parameter, the map or the world file is invalid; the message says which."""


@dataclass(frozen=True)
class Param:
    """One simulator parameter.

    Attributes:
        name: Parameter name.
        default: Default value (None: type-only, or taken from the world file).
        kind: ``float``, ``int``, ``bool``, ``str``, ``int[]`` or ``str[]``.
        doc: One line for ``--help`` and the parameter descriptor.
    """

    name: str
    default: Any
    kind: str
    doc: str


PARAMETERS: tuple[Param, ...] = (
    Param("map_yaml", str(DEFAULT_MAP_YAML), "str", "map_server yaml the planner and /map use"),
    Param("world", str(DEFAULT_WORLD_PATH), "str", "world file (spawn, footprint, markers)"),
    Param("speed", 1.0, "float", "simulated seconds per wall second (20 = 20x real time)"),
    Param("physics_hz", 50.0, "float", "physics steps per simulated second"),
    Param("max_update_hz", 100.0, "float", "wall-clock cap on /clock, /tf, odometry updates"),
    Param("publish_hz", 30.0, "float", "odometry and /tf rate, per simulated second"),
    Param("feedback_hz", 10.0, "float", "action feedback rate, per simulated second"),
    Param("max_linear", 0.5, "float", "linear velocity limit, m/s"),
    Param("max_angular", 1.0, "float", "angular velocity limit, rad/s"),
    Param("speed_scale", 1.0, "float", "factor on both velocity limits (fault: slow robot)"),
    Param("xy_goal_tolerance", 0.25, "float", "goal position tolerance, m"),
    Param("yaw_goal_tolerance", 0.25, "float", "goal heading tolerance, rad"),
    Param("robot_radius", None, "float", "inflation radius, m (default: world footprint)"),
    Param("spawn_x", None, "float", "spawn x, m (default: world spawn)"),
    Param("spawn_y", None, "float", "spawn y, m (default: world spawn)"),
    Param("spawn_yaw", None, "float", "spawn yaw, rad (default: world spawn)"),
    Param("auto_localize", True, "bool",
          "publish map->odom from the start; false: only after /initialpose, as AMCL"),
    Param("autostart", True, "bool",
          "lifecycle managers bring the Nav2 nodes up at start (Nav2 bringup's autostart)"),
    Param("odom_topic", "/odometry/filtered", "str",
          "odometry topic (the ROSbot's fused odometry, which Nav2's params read)"),
    Param("global_frame", "map", "str", "map frame"),
    Param("odom_frame", "odom", "str", "odometry frame"),
    Param("base_frame", "base_link", "str", "robot frame"),
    Param("trace_file", "", "str", "JSON Lines trace of poses and goal events ('' = off)"),
    Param("trace_period_s", 0.2, "float", "simulated seconds between trace pose lines"),
    Param("reject_goals", False, "bool", "fault: reject every goal"),
    Param("abort_goal_numbers", None, "int[]", "fault: abort these accepted goals (1-based)"),
    Param("abort_delay_s", 1.0, "float", "fault: simulated seconds before such an abort"),
    Param("accept_delay_s", 0.0, "float", "fault: wall seconds before a goal is answered"),
    Param("blocked_zones", None, "str[]",
          "fault: extra obstacles, 'x:y:radius' or 'marker[:radius]'"),
)

_TYPES = {
    "float": Parameter.Type.DOUBLE,
    "int": Parameter.Type.INTEGER,
    "bool": Parameter.Type.BOOL,
    "str": Parameter.Type.STRING,
    "int[]": Parameter.Type.INTEGER_ARRAY,
    "str[]": Parameter.Type.STRING_ARRAY,
}


@dataclass(frozen=True)
class SimSettings:
    """Validated simulator settings (see :data:`PARAMETERS` for the meaning of each).

    Attributes:
        map_yaml: Map file.
        world: World file.
        speed: Speed factor.
        physics_hz: Physics rate, simulated Hz.
        max_update_hz: Wall-clock cap on publishing.
        publish_hz: Odometry and ``/tf`` rate, simulated Hz.
        feedback_hz: Feedback rate, simulated Hz.
        limits: Drive limits (after ``speed_scale``) and goal tolerances.
        robot_radius: Inflation radius, metres.
        spawn: Spawn pose.
        auto_localize: Localised from the start.
        autostart: The lifecycle managers start their nodes at once.
        odom_topic: Where odometry is published.
        global_frame: Map frame.
        odom_frame: Odometry frame.
        base_frame: Robot frame.
        trace_file: Trace path or None.
        trace_period_s: Trace sampling period, simulated seconds.
        faults: Injected faults.
    """

    map_yaml: Path
    world: Path
    speed: float
    physics_hz: float
    max_update_hz: float
    publish_hz: float
    feedback_hz: float
    limits: DriveLimits
    robot_radius: float
    spawn: Pose2D
    auto_localize: bool
    autostart: bool
    odom_topic: str
    global_frame: str
    odom_frame: str
    base_frame: str
    trace_file: Path | None
    trace_period_s: float
    faults: Faults = field(default_factory=Faults)


def declare(node: Node, param: Param, default: Any) -> Any:
    """Declare ``param`` on ``node`` and return its value (None when unset)."""
    descriptor = ParameterDescriptor(
        description=param.doc, dynamic_typing=param.kind in ("float", "int")
    )
    if default is None:
        node.declare_parameter(param.name, _TYPES[param.kind], descriptor)
    else:
        node.declare_parameter(param.name, default, descriptor)
    try:
        return node.get_parameter(param.name).value
    except ParameterUninitializedException:
        return None


def number(name: str, value: Any, *, positive: bool = True) -> float:
    """Return ``value`` as a float, or raise :class:`SimConfigError` naming the parameter."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise SimConfigError(f"parameter {name}: expected a number, got {value!r}")
    if positive and value <= 0.0:
        raise SimConfigError(f"parameter {name}: expected a positive number, got {value!r}")
    return float(value)


def read_settings(node: Node) -> tuple[SimSettings, World, OccupancyGrid]:
    """Declare the simulator's parameters on ``node``, validate them, load world and map.

    Args:
        node: The ``sar_sim`` node (parameter overrides come from its ``--ros-args``).

    Returns:
        ``(settings, world, map grid)``.

    Raises:
        SimConfigError: A parameter is invalid, or the map or world cannot be loaded.
    """
    by_name = {p.name: p for p in PARAMETERS}
    raw: dict[str, Any] = {}
    for name in ("map_yaml", "world"):
        raw[name] = declare(node, by_name[name], by_name[name].default)
    try:
        world = load_world(raw["world"])
        grid = load_map(raw["map_yaml"])
    except (WorldError, MapError) as exc:
        raise SimConfigError(str(exc)) from exc
    world_defaults = {
        "robot_radius": world.robot.footprint_radius,
        "spawn_x": world.robot.spawn.x,
        "spawn_y": world.robot.spawn.y,
        "spawn_yaw": world.robot.spawn.yaw,
    }
    for param in PARAMETERS:
        if param.name not in raw:
            raw[param.name] = declare(node, param, world_defaults.get(param.name, param.default))

    num = {
        name: number(name, raw[name])
        for name in ("speed", "physics_hz", "max_update_hz", "publish_hz", "feedback_hz",
                     "max_linear", "max_angular", "speed_scale", "xy_goal_tolerance",
                     "yaw_goal_tolerance", "robot_radius", "trace_period_s")
    }
    spawn = Pose2D(*(number(n, raw[n], positive=False)
                     for n in ("spawn_x", "spawn_y", "spawn_yaw")))
    markers = {m.name: (m.x, m.y) for m in world.markers}
    try:
        faults = make_faults(
            reject_goals=raw["reject_goals"],
            abort_goal_numbers=raw["abort_goal_numbers"] or (),
            abort_delay_s=number("abort_delay_s", raw["abort_delay_s"], positive=False),
            accept_delay_s=number("accept_delay_s", raw["accept_delay_s"], positive=False),
            blocked_zones=raw["blocked_zones"] or (),
            markers=markers,
        )
    except FaultConfigError as exc:
        raise SimConfigError(f"parameter {exc}") from exc
    limits = DriveLimits(
        max_linear=num["max_linear"] * num["speed_scale"],
        max_angular=num["max_angular"] * num["speed_scale"],
        xy_tolerance=num["xy_goal_tolerance"],
        yaw_tolerance=num["yaw_goal_tolerance"],
    )
    settings = SimSettings(
        map_yaml=Path(raw["map_yaml"]),
        world=Path(raw["world"]),
        **{n: num[n] for n in ("speed", "physics_hz", "max_update_hz", "publish_hz",
                               "feedback_hz", "robot_radius", "trace_period_s")},
        **{n: bool(raw[n]) for n in ("auto_localize", "autostart")},
        **{n: str(raw[n]) for n in ("odom_topic", "global_frame", "odom_frame", "base_frame")},
        limits=limits,
        spawn=spawn,
        trace_file=Path(raw["trace_file"]) if raw["trace_file"] else None,
        faults=faults,
    )
    return settings, world, grid
