"""The simulator's parameters (``sar_sim``), declared once; no ROS here.

:data:`SIM_PARAMETERS` is what :mod:`.settings` declares on the node and validates, what
``sar-sim --help`` and ``sar-tree faults`` print, what ``sar-tree run`` checks
``--sim-param`` against, and where the launch file and ``sar-tree run --speed`` take the
speed's default from. Integers are accepted where a number is expected (``speed:=20``).
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

from sar_framework.engine.param import Param
from sar_framework.mission.params_check import USE_SIM_TIME

DEFAULT_MAP_YAML = Path(__file__).resolve().parents[2] / "maps" / "final_project_map.yaml"
"""The map the simulator runs on unless told otherwise (``maps/final_project_map.yaml``)."""
DEFAULT_NAMED_RADIUS = 0.6
"""Radius, metres, of a blocked area given by a name only (``sar-tree run`` resolves names)."""

SPEED = Param("speed", float, 20.0, "simulated seconds per wall second (20 = 20x real time); "
              "may change at run time",
              exclusive_minimum=0.0, maximum=1000.0)
"""The speed factor: its one default and its one rule (the simulator's, ``sar-tree run
--speed``'s, the launch file's ``speed``'s and :class:`~.clock.SimClock`'s)."""


def _rate(name: str, default: float, description: str, unit: str = "Hz") -> Param:
    return Param(name, float, default, description, exclusive_minimum=0.0, unit=unit)


RUNTIME_FAULTS: tuple[Param, ...] = (
    Param("phantom_obstacles", list[str], None,
          "fault (run-time): circles in both costmaps, never in the map, that costmap clearing "
          "removes: 'x:y:radius' (m), as blocked_areas"),
    Param("stuck_recoveries", int, 0,
          "fault (run-time): the controller makes no progress (FollowPath 105 after "
          "movement_time_allowance) until this many spin/backup/drive_on_heading motions "
          "have completed; 0 = never stuck", minimum=0),
    Param("movement_time_allowance", float, 10.0,
          "progress checker: a stuck controller fails after this long (simulated)",
          exclusive_minimum=0.0, unit="s"),
)
"""The faults that may be set while the simulator runs (``ros2 param set``); ``~/reset``
re-arms them."""

SIM_PARAMETERS: tuple[Param, ...] = (
    Param("map_yaml", str, str(DEFAULT_MAP_YAML), "the map (nav2 map_server's yaml: image, "
          "resolution, origin, negate, occupied_thresh, free_thresh, mode) the planner and "
          "/map use"),
    SPEED,
    _rate("physics_hz", 50.0, "physics steps per simulated second"),
    _rate("max_update_hz", 50.0, "wall-clock cap on /clock, /tf and odometry updates (at "
          "20x, one /clock per 0.4 s simulated: each 2 Hz tick still has its own)"),
    _rate("publish_hz", 30.0, "odometry and /tf rate, per simulated second"),
    _rate("feedback_hz", 10.0, "action feedback rate, per simulated second"),
    _rate("max_linear", 0.5, "linear velocity limit", "m/s"),
    _rate("max_angular", 1.0, "angular velocity limit", "rad/s"),
    _rate("speed_scale", 1.0, "fault: factor on both velocity limits (a slow robot)", ""),
    _rate("xy_goal_tolerance", 0.25, "goal position tolerance", "m"),
    _rate("yaw_goal_tolerance", 0.25, "goal heading tolerance", "rad"),
    Param("robot_radius", float, 0.22, "the robot's footprint radius, Nav2's robot_radius "
          "(the inflation radius; a ROSbot's)", exclusive_minimum=0.0, unit="m"),
    Param("spawn_x", float, 0.0, "spawn x, on a free cell of the map", unit="m"),
    Param("spawn_y", float, 0.0, "spawn y, on a free cell of the map", unit="m"),
    Param("spawn_yaw", float, 0.0, "spawn heading", unit="rad"),
    Param("auto_localize", bool, True,
          "publish map->odom from the start; false: only after /initialpose, as AMCL"),
    Param("autostart", bool, True,
          "lifecycle managers bring the Nav2 nodes up at start (Nav2 bringup's autostart)"),
    Param("odom_topic", str, "/odometry/filtered",
          "odometry topic (the ROSbot's fused odometry, which Nav2's params read)"),
    Param("global_frame", str, "map", "map frame"),
    Param("odom_frame", str, "odom", "odometry frame"),
    Param("base_frame", str, "base_link", "robot frame"),
    Param("fleet_file", str, "", "fleet file: robots (name, pose), each under its namespace "
          "('' = one robot, no namespace; docs/how-to/fleet.md)"),
    Param("trace_file", str, "", "JSON Lines trace of poses and goal events ('' = off); with "
          "a fleet_file, one per robot in a folder of its name beside it (DIR/robot1/NAME)"),
    _rate("trace_period_s", 0.2, "simulated seconds between trace pose lines", "s"),
    Param("reject_goals", bool, False, "fault: the navigation server rejects every goal"),
    Param("abort_goal_numbers", list[int], None,
          "fault: these accepted goals (1-based) abort after abort_delay_s"),
    Param("abort_delay_s", float, 1.0, "fault: how long an aborted goal runs first "
          "(simulated)", minimum=0.0, unit="s"),
    Param("accept_delay_wall_s", float, 0.0, "fault: the server answers a goal request this late "
          "(wall clock)", minimum=0.0, unit="s"),
    Param("blocked_areas", list[str], None,
          "fault (run-time): circles added to the map as obstacles (walls no costmap "
          "clearing removes): 'x:y:radius' (m); sar-tree run also takes 'name[:radius]', a "
          f"place its app names (radius {DEFAULT_NAMED_RADIUS:g} m unless given)"),
    *RUNTIME_FAULTS,
    USE_SIM_TIME,
)
"""Every parameter ``sar_sim`` reads."""

RUNTIME_NAMES = frozenset({SPEED.name, "blocked_areas", *(p.name for p in RUNTIME_FAULTS)})
"""The parameters that may change while the simulator runs (the others are fixed)."""


SPAWN_NAMES = ("spawn_x", "spawn_y", "spawn_yaw")
"""The parameters of the spawn pose (``sar-tree run --spawn``, the launch's ``spawn``)."""


def parse_pose(text: str) -> tuple[float, float, float]:
    """``"X,Y[,YAW]"`` (metres, metres, radians; ``;`` or spaces also separate) as numbers.

    Raises:
        ValueError: Not two or three finite numbers; the message says what is expected.
    """
    parts = [p for p in re.split(r"[,;\s]+", text.strip()) if p]
    try:
        numbers = [float(p) for p in parts]
    except ValueError:
        numbers = []
    if len(numbers) not in (2, 3) or not all(math.isfinite(n) for n in numbers):
        raise ValueError(f"{text!r}: expected X,Y[,YAW] (metres, metres, radians), "
                         "e.g. 1.5,-2.0,1.57")
    return numbers[0], numbers[1], numbers[2] if len(numbers) == 3 else 0.0


def pose_entries(pose: tuple[float, float, float]) -> list[str]:
    """The simulator's spawn parameters for ``pose``, as ``NAME:=VALUE`` entries."""
    return [f"{name}:={value!r}" for name, value in zip(SPAWN_NAMES, pose, strict=True)]


def sim_default(name: str) -> Any:
    """The default of the simulator parameter ``name`` (from :data:`SIM_PARAMETERS`)."""
    return next(p.default for p in SIM_PARAMETERS if p.name == name)
