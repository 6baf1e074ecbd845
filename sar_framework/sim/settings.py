"""The simulator's parameters declared on ``sar_sim`` and validated into :class:`SimSettings`.

The table, with each parameter's type, default, unit and range, is
:data:`sar_framework.sim.params.SIM_PARAMETERS`; the rule for each value is the table's
(:meth:`~sar_framework.engine.param.Param.problem`), as ``sar-tree run`` applies it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from sar_framework.mission.params_file import ParamsError
from sar_framework.ros.parameters import declare_table
from sar_framework.sim.drive import DriveLimits
from sar_framework.sim.faults import FaultConfigError, Faults, make_faults
from sar_framework.sim.fleet_file import FleetFileError, crowded_spawns, load_fleet
from sar_framework.sim.occupancy import MapError, OccupancyGrid, load_map, spawn_problem
from sar_framework.sim.params import DEFAULT_MAP_YAML, SIM_PARAMETERS
from sar_framework.sim.world import Pose2D

if TYPE_CHECKING:
    from rclpy.node import Node

__all__ = ["DEFAULT_MAP_YAML", "SimConfigError", "SimSettings", "fleet_spawns",
           "read_settings"]


class SimConfigError(ValueError):
    """A simulator parameter or the map is invalid; the message says which."""


@dataclass(frozen=True)
class SimSettings:
    """Validated simulator settings (see :data:`~.params.SIM_PARAMETERS` for each).

    Attributes:
        map_yaml: Map file (absolute).
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
        fleet_file: Fleet file or None (one robot, root namespace).
        trace_period_s: Trace sampling period, simulated seconds.
        faults: Injected faults.
    """

    map_yaml: Path
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
    fleet_file: Path | None = None
    faults: Faults = field(default_factory=Faults)


def read_settings(node: Node) -> tuple[SimSettings, OccupancyGrid]:
    """Declare the simulator's parameters on ``node``, validate them, load the map.

    Args:
        node: The ``sar_sim`` node (parameter overrides come from its ``--ros-args``).

    Returns:
        ``(settings, map grid)``.

    Raises:
        SimConfigError: A parameter is invalid, the map cannot be loaded, or the spawn pose
            is not on a free cell of it.
    """
    try:
        raw = declare_table(node, SIM_PARAMETERS)
        grid = load_map(raw["map_yaml"])
    except ParamsError as exc:
        raise SimConfigError(f"parameter {exc.key}: {exc.problem}") from exc
    except MapError as exc:
        raise SimConfigError(f"parameter map_yaml: {exc}") from exc
    num = {name: float(value) for name, value in raw.items()
           if isinstance(value, (int, float)) and not isinstance(value, bool)}
    spawn = Pose2D(num["spawn_x"], num["spawn_y"], num["spawn_yaw"])
    problem = spawn_problem(grid, spawn.x, spawn.y)
    if problem and not raw["fleet_file"]:
        raise SimConfigError(f"parameters spawn_x, spawn_y on {raw['map_yaml']}: {problem}")
    try:
        faults = make_faults(
            reject_goals=raw["reject_goals"],
            abort_goal_numbers=raw["abort_goal_numbers"] or (),
            abort_delay_s=num["abort_delay_s"],
            accept_delay_wall_s=num["accept_delay_wall_s"],
            blocked_areas=raw["blocked_areas"] or (),
            phantom_obstacles=raw["phantom_obstacles"] or (),
            stuck_recoveries=int(raw["stuck_recoveries"]),
            movement_time_allowance=num["movement_time_allowance"],
        )
    except FaultConfigError as exc:
        raise SimConfigError(f"parameter {exc}") from exc
    limits = DriveLimits(
        max_linear=num["max_linear"] * num["speed_scale"],
        max_angular=num["max_angular"] * num["speed_scale"],
        xy_tolerance=num["xy_goal_tolerance"],
        yaw_tolerance=num["yaw_goal_tolerance"],
    )
    return SimSettings(
        map_yaml=Path(raw["map_yaml"]).absolute(),
        **{n: num[n] for n in ("speed", "physics_hz", "max_update_hz", "publish_hz",
                               "feedback_hz", "robot_radius", "trace_period_s")},
        **{n: bool(raw[n]) for n in ("auto_localize", "autostart")},
        **{n: str(raw[n]) for n in ("odom_topic", "global_frame", "odom_frame", "base_frame")},
        limits=limits,
        spawn=spawn,
        trace_file=Path(raw["trace_file"]) if raw["trace_file"] else None,
        fleet_file=Path(raw["fleet_file"]) if raw["fleet_file"] else None,
        faults=faults,
    ), grid


def trace_path(trace_file: Path, robot: str) -> Path:
    """A robot's trace file: ``trace_file`` itself, or ``DIR/<robot>/NAME`` in a fleet.

    Args:
        trace_file: The ``trace_file`` parameter.
        robot: The robot's namespace, "" outside a fleet.
    """
    return trace_file.parent / robot / trace_file.name if robot else trace_file


def fleet_spawns(settings: SimSettings) -> list[tuple[str, Pose2D]]:
    """The robots to simulate: ``(namespace, spawn)``; ``[("", spawn)]`` without a fleet file.

    Raises:
        SimConfigError: The fleet file is malformed (each problem at its ``file:line:col``),
            or two spawn poses are closer than two footprints (both lines named).
    """
    if settings.fleet_file is None:
        return [("", settings.spawn)]
    try:
        robots = load_fleet(settings.fleet_file)
    except FleetFileError as exc:
        raise SimConfigError(f"fleet_file:\n{exc}") from exc
    crowded = crowded_spawns(robots, 2.0 * settings.robot_radius)
    if crowded:
        raise SimConfigError(crowded[0])
    return [(robot.name, robot.spawn) for robot in robots]
