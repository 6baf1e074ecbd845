"""The composed simulator: physics loop, ``/clock``, TF, odometry, map, AMCL and Nav2 nodes.

One process, three nodes sharing one executor:

- ``sar_sim``: parameters, ``/clock``, ``/tf`` (``map -> odom -> base_link``), ``/odom``,
  ``/map`` (TRANSIENT_LOCAL) and the physics loop (its own thread, paced by
  :class:`~sar_framework.sim.clock.SimClock`, never blocked by ROS callbacks);
- ``amcl`` (:class:`~sar_framework.sim.amcl.AmclStandIn`);
- ``bt_navigator`` (:class:`~sar_framework.sim.nav_server.NavigateToPoseServer`).

Parameters are declared on ``sar_sim`` (see :data:`PARAMETERS`); integers are accepted
where a float is expected (``speed:=20``).

Simulated time: the simulator *is* the time source, so its own nodes' ROS clocks follow
simulated time directly (an rclpy ``TimeSource`` fed by the physics loop) instead of
subscribing to the ``/clock`` they publish; three such subscriptions cost a quarter of a
core at 100 updates per second. Their ``use_sim_time`` parameter therefore stays false,
yet ``node.get_clock().now()`` is simulated time, as with ``use_sim_time:=true``.
"""

from __future__ import annotations

import math
import threading
import time
import traceback
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from nav_msgs.msg import OccupancyGrid as OccupancyGridMsg
from nav_msgs.msg import Odometry
from rcl_interfaces.msg import ParameterDescriptor, SetParametersResult
from rclpy.exceptions import ParameterUninitializedException
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.time_source import TimeSource
from rosgraph_msgs.msg import Clock
from tf2_msgs.msg import TFMessage

from sar_framework.ros.qos import latched_qos
from sar_framework.sim import messages
from sar_framework.sim.amcl import AmclStandIn
from sar_framework.sim.clock import NS_PER_S, SimClock
from sar_framework.sim.drive import DiffDrive, DriveLimits
from sar_framework.sim.faults import FaultConfigError, Faults, make_faults, with_blocked_zones
from sar_framework.sim.nav_server import NavigateToPoseServer
from sar_framework.sim.navigation import Goal, Navigator, RobotState
from sar_framework.sim.occupancy import DEFAULT_MAP_PREFIX, MapError, OccupancyGrid, load_map
from sar_framework.sim.planner import GridPlanner
from sar_framework.sim.trace import TraceWriter
from sar_framework.sim.world import DEFAULT_WORLD_PATH, Pose2D, World, WorldError, load_world

DEFAULT_MAP_YAML = DEFAULT_MAP_PREFIX.with_name(DEFAULT_MAP_PREFIX.name + ".yaml")
"""The committed course map (``maps/final_project_map.yaml``)."""

NODE_NAME = "sar_sim"


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
    Param("max_update_hz", 100.0, "float", "wall-clock cap on /clock, /tf, /odom updates"),
    Param("publish_hz", 30.0, "float", "/odom and /tf rate, per simulated second"),
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
        publish_hz: ``/odom``/``/tf`` rate, simulated Hz.
        feedback_hz: Feedback rate, simulated Hz.
        limits: Drive limits (after ``speed_scale``) and goal tolerances.
        robot_radius: Inflation radius, metres.
        spawn: Spawn pose.
        auto_localize: Localised from the start.
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
    global_frame: str
    odom_frame: str
    base_frame: str
    trace_file: Path | None
    trace_period_s: float
    faults: Faults = field(default_factory=Faults)


def _declare(node: Node, param: Param, default: Any) -> Any:
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


def _number(name: str, value: Any, *, positive: bool = True) -> float:
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
        raw[name] = _declare(node, by_name[name], by_name[name].default)
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
            raw[param.name] = _declare(node, param, world_defaults.get(param.name, param.default))

    num = {
        name: _number(name, raw[name])
        for name in ("speed", "physics_hz", "max_update_hz", "publish_hz", "feedback_hz",
                     "max_linear", "max_angular", "speed_scale", "xy_goal_tolerance",
                     "yaw_goal_tolerance", "robot_radius", "trace_period_s")
    }
    spawn = Pose2D(*(_number(n, raw[n], positive=False)
                     for n in ("spawn_x", "spawn_y", "spawn_yaw")))
    markers = {m.name: (m.x, m.y) for m in world.markers}
    try:
        faults = make_faults(
            reject_goals=raw["reject_goals"],
            abort_goal_numbers=raw["abort_goal_numbers"] or (),
            abort_delay_s=_number("abort_delay_s", raw["abort_delay_s"], positive=False),
            accept_delay_s=_number("accept_delay_s", raw["accept_delay_s"], positive=False),
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
        speed=num["speed"],
        physics_hz=num["physics_hz"],
        max_update_hz=num["max_update_hz"],
        publish_hz=num["publish_hz"],
        feedback_hz=num["feedback_hz"],
        limits=limits,
        robot_radius=num["robot_radius"],
        spawn=spawn,
        auto_localize=bool(raw["auto_localize"]),
        global_frame=raw["global_frame"],
        odom_frame=raw["odom_frame"],
        base_frame=raw["base_frame"],
        trace_file=Path(raw["trace_file"]) if raw["trace_file"] else None,
        trace_period_s=num["trace_period_s"],
        faults=faults,
    )
    return settings, world, grid


class Simulator:
    """The whole embedded simulator; add :attr:`nodes` to a ``MultiThreadedExecutor``.

    Construction reads the parameters and loads everything; :meth:`start` publishes the
    map and starts the physics thread; :meth:`stop` aborts a goal in flight, stops the
    physics and closes the trace.

    Raises:
        SimConfigError: Invalid parameters, map or world (the node is destroyed first).
    """

    def __init__(self) -> None:
        self.node = Node(NODE_NAME)
        try:
            self.settings, self.world, self.grid = read_settings(self.node)
        except SimConfigError:
            self.node.destroy_node()
            raise
        s = self.settings
        self.clock = SimClock(step_s=1.0 / s.physics_hz, speed=s.speed)
        self._clock_lock = threading.Lock()
        self._now_ns = 0
        planning_grid = with_blocked_zones(self.grid, s.faults.blocked_zones)
        self.planner = GridPlanner(planning_grid, robot_radius=s.robot_radius)
        try:
            self.trace = TraceWriter(s.trace_file, s.trace_period_s) if s.trace_file else None
        except OSError as exc:
            self.node.destroy_node()
            raise SimConfigError(f"parameter trace_file: cannot write {s.trace_file}: "
                                 f"{exc.strerror or exc}") from exc
        self.navigator = Navigator(
            DiffDrive(s.spawn, s.limits), self.planner, s.faults, self._on_goal_event
        )
        self.amcl = AmclStandIn(
            lambda: self.navigator.state().pose, self.now_ns,
            global_frame=s.global_frame, localized=s.auto_localize,
        )
        self.nav = NavigateToPoseServer(
            self.navigator, self.now_ns, lambda: self.amcl.localized,
            faults=s.faults, global_frame=s.global_frame,
            feedback_period_s=1.0 / s.feedback_hz, event_sink=self._on_request_event,
        )
        self._time_source = TimeSource()  # no node: fed by the physics loop, no subscription
        self._time_source.ros_time_is_active = True
        for node in self.nodes:
            self._time_source.attach_clock(node.get_clock())
        self._clock_pub = self.node.create_publisher(Clock, "/clock", 10)
        self._tf_pub = self.node.create_publisher(TFMessage, "/tf", 100)
        self._odom_pub = self.node.create_publisher(Odometry, "/odom", 10)
        self._map_pub = self.node.create_publisher(OccupancyGridMsg, "/map", latched_qos())
        self.node.add_on_set_parameters_callback(self._on_set_parameters)
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._physics_loop, name="sim-physics",
                                        daemon=True)
        self._wall_start = 0.0
        self._new_speed: float | None = None

    @property
    def nodes(self) -> list[Node]:
        """Every node of the simulator (to add to the executor)."""
        return [self.node, self.amcl.node, self.nav.node]

    @property
    def alive(self) -> bool:
        """Whether the physics thread runs (False before :meth:`start` or after a crash)."""
        return self._thread.is_alive()

    def now_ns(self) -> int:
        """Simulated time, nanoseconds (thread-safe)."""
        with self._clock_lock:
            return self._now_ns

    # ------------------------------------------------------------------ lifecycle

    def start(self) -> None:
        """Publish the map and the initial state, then start the physics thread."""
        s = self.settings
        self._map_pub.publish(messages.occupancy_grid_msg(self.grid, s.global_frame, 0))
        self._publish_state(0, self.navigator.state())
        self._clock_pub.publish(Clock())
        if self.trace is not None:
            spawn = s.spawn
            self.trace.event(0.0, "start", x=spawn.x, y=spawn.y, yaw=spawn.yaw, speed=s.speed,
                             map=str(s.map_yaml), world=str(s.world))
        self._wall_start = time.monotonic()
        self._thread.start()

    def stop(self, reason: str = "simulator shutting down") -> bool:
        """Abort a goal in flight, stop physics, close the trace.

        Args:
            reason: ``error_msg`` of a goal in flight.

        Returns:
            Whether a goal was in flight (keep spinning briefly so its result goes out).
        """
        aborted = self.nav.close(reason)
        self._stop.set()
        if self._thread.is_alive():
            self._thread.join(timeout=1.0)
        wall = time.monotonic() - self._wall_start if self._wall_start else 0.0
        state = self.navigator.state()
        sim_s = self.now_ns() / NS_PER_S
        rtf = sim_s / wall if wall > 0 else 0.0
        self.node.get_logger().info(
            f"Stopped at {sim_s:.1f} s simulated after {wall:.1f} s wall ({rtf:.1f}x real "
            f"time); path travelled {state.odometry:.2f} m, "
            f"{self.navigator.accepted_count} goals."
        )
        if self.trace is not None:
            self.trace.event(sim_s, "end", path_m=state.odometry,
                             goals=self.navigator.accepted_count, wall_s=wall, rtf=rtf,
                             dropped_steps=self.clock.dropped_steps)
            self.trace.close()
        return aborted is not None

    def destroy(self) -> None:
        """Destroy every node (after the executor has stopped)."""
        self.nav.destroy()
        self.amcl.node.destroy_node()
        self.node.destroy_node()

    def ready_message(self) -> str:
        """The start-up log line (tests and the runner wait for ``ready``)."""
        s = self.settings
        faults = f"; faults: {s.faults.describe()}" if s.faults.any else ""
        return (
            f"ready: navigate_to_pose served, /clock at {s.speed:g}x real time "
            f"(physics {s.physics_hz:g} Hz), map {s.map_yaml} "
            f"({self.grid.width}x{self.grid.height}), spawn ({s.spawn.x:.2f}, {s.spawn.y:.2f}, "
            f"yaw {s.spawn.yaw:.2f}){faults}"
        )

    # ------------------------------------------------------------------ physics

    def _physics_loop(self) -> None:
        """Run :meth:`_physics` and log a crash (the process then stops, see ``alive``)."""
        try:
            self._physics()
        except Exception:
            self.node.get_logger().fatal(f"physics loop crashed:\n{traceback.format_exc()}")
            raise

    def _physics(self) -> None:
        """Step physics as fast as ``speed`` allows; publish at most ``max_update_hz``."""
        s = self.settings
        clock = self.clock
        dt = clock.step_s
        min_period = 1.0 / s.max_update_hz
        publish_period_ns = round(NS_PER_S / s.publish_hz)
        next_publish_ns = 0
        clock.start(time.monotonic())
        while not self._stop.is_set():
            if self._new_speed is not None:
                clock.speed, self._new_speed = self._new_speed, None
            if self.navigator.planning:
                clock.hold()  # a plan takes no simulated time
                self._stop.wait(0.001)
                continue
            wall = time.monotonic()
            steps = clock.due_steps(wall)
            for _ in range(steps):
                now_ns = clock.advance()
                self.navigator.step(dt, now_ns / NS_PER_S)
            if steps:
                now_ns = clock.now_ns
                with self._clock_lock:
                    self._now_ns = now_ns
                clock_msg = Clock(clock=messages.time_msg(now_ns))
                self._time_source.clock_callback(clock_msg)
                self._clock_pub.publish(clock_msg)
                state = self.navigator.state()
                if now_ns >= next_publish_ns:
                    self._publish_state(now_ns, state)
                    next_publish_ns = now_ns + publish_period_ns
                if self.trace is not None:
                    self.trace.pose(now_ns / NS_PER_S, state.pose.x, state.pose.y,
                                    state.pose.yaw, state.odometry)
            after = time.monotonic()
            pause = max(clock.wall_until_next_step(after), min_period - (after - wall))
            self._stop.wait(pause)

    def _publish_state(self, now_ns: int, state: RobotState) -> None:
        """Publish ``/clock``-stamped ``/tf`` and ``/odom`` for ``state``."""
        s = self.settings
        odom_pose = messages.relative_pose(s.spawn, state.pose)
        transforms = [messages.transform(s.odom_frame, s.base_frame, odom_pose, now_ns)]
        if self.amcl.localized:
            transforms.insert(0, messages.transform(s.global_frame, s.odom_frame, s.spawn,
                                                    now_ns))
        self._tf_pub.publish(TFMessage(transforms=transforms))
        self._odom_pub.publish(messages.odometry(
            odom_pose, (state.linear, state.angular), (s.odom_frame, s.base_frame), now_ns
        ))

    # ------------------------------------------------------------------ events

    def _on_goal_event(self, goal: Goal, sim_s: float, robot: RobotState) -> None:
        """Trace goal starts and ends (called with the navigator's lock held)."""
        if self.trace is None:
            return
        target = goal.target
        fields: dict[str, Any] = {"goal": goal.number, "x": target.x, "y": target.y,
                                  "yaw": target.yaw, "path_m": robot.odometry}
        if goal.active:
            self.trace.event(sim_s, "accepted", **fields)
            return
        fields.update(robot_x=robot.pose.x, robot_y=robot.pose.y, robot_yaw=robot.pose.yaw)
        if goal.error_code or goal.error_msg:
            fields.update(error_code=goal.error_code, error_msg=goal.error_msg)
        self.trace.event(sim_s, goal.outcome.value, **fields)

    def _on_request_event(self, event: str, **fields: Any) -> None:
        """Trace goal requests the navigator never saw (rejections)."""
        if self.trace is not None:
            self.trace.event(self.now_ns() / NS_PER_S, event, **fields)

    def _on_set_parameters(self, params: list[Parameter]) -> SetParametersResult:
        """Allow ``speed`` to change at run time; every other simulator parameter is fixed."""
        fixed = {p.name for p in PARAMETERS} - {"speed"}
        for param in params:
            if param.name in fixed:
                return SetParametersResult(
                    successful=False, reason=f"{param.name} cannot change at run time"
                )
            if param.name == "speed":
                try:
                    speed = _number("speed", param.value)
                except SimConfigError as exc:
                    return SetParametersResult(successful=False, reason=str(exc))
                self._new_speed = speed  # applied by the physics thread
                self.node.get_logger().info(f"Speed set to {speed:g}x real time.")
        return SetParametersResult(successful=True)
