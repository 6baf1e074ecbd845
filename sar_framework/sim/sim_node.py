"""The composed simulator: physics loop, ``/clock``, TF, odometry and Nav2's nodes.

One process, one executor, the nodes of a Jazzy ``bringup_launch.py`` per robot (one
:class:`~sar_framework.sim.robot_stack.RobotStack` each: one in the root namespace, or one
per robot of the ``fleet_file`` in its namespace, sharing the world, ``/clock`` and the
physics loop; docs/how-to/fleet.md):

- ``sar_sim``: parameters (see :mod:`~sar_framework.sim.settings`), ``/clock``, ``/tf``
  (``map -> odom`` while AMCL is localised, ``odom -> base_link``), odometry on
  ``/odometry/filtered`` (as the ROSbot's EKF), and the physics loop (its own thread, paced
  by :class:`~sar_framework.sim.clock.SimClock`, never blocked by ROS callbacks);
- lifecycle nodes ``map_server``, ``amcl`` (``lifecycle_manager_localization``) and
  ``controller_server``, ``smoother_server``, ``planner_server``, ``behavior_server``,
  ``bt_navigator``, ``waypoint_follower`` (``lifecycle_manager_navigation``), plus the
  costmap nodes ``/global_costmap/global_costmap`` and ``/local_costmap/local_costmap``
  (:mod:`~sar_framework.sim.costmap_servers`);
- run-time faults (:mod:`~sar_framework.sim.live_params`) and ``/sar_sim/reset``
  (``std_srvs/srv/Trigger``): every running goal ends ABORTED, the robot is at rest at its
  spawn pose (localised as at start-up), the faults are re-armed, goal numbers restart.

Simulated time: the simulator *is* the time source, so its own nodes' ROS clocks follow
simulated time directly (an rclpy ``TimeSource`` fed by the physics loop) instead of
subscribing to the ``/clock`` they publish; a dozen such subscriptions would cost most of a
core at 100 updates per second. Their ``use_sim_time`` parameter therefore stays false,
yet ``node.get_clock().now()`` is simulated time, as with ``use_sim_time:=true``.
"""

from __future__ import annotations

import functools
import threading
import time
import traceback
from typing import Any

from rclpy.node import Node
from rclpy.time_source import TimeSource
from rosgraph_msgs.msg import Clock
from std_srvs.srv import Trigger

from sar_framework.sim import messages
from sar_framework.sim.clock import NS_PER_S, SimClock
from sar_framework.sim.goals import Goal, RobotState
from sar_framework.sim.lifecycle import take_not_offered
from sar_framework.sim.live_params import LiveParameters
from sar_framework.sim.robot_stack import RobotStack
from sar_framework.sim.settings import (
    DEFAULT_MAP_YAML,
    SimConfigError,
    SimSettings,
    fleet_spawns,
    read_settings,
    trace_path,
)
from sar_framework.sim.trace import TraceWriter

__all__ = ["DEFAULT_MAP_YAML", "NODE_NAME", "SimConfigError", "SimSettings", "Simulator"]

NODE_NAME = "sar_sim"


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
            self.settings, self.grid = read_settings(self.node)
        except SimConfigError:
            self.node.destroy_node()
            raise
        s = self.settings
        # A stall costs at most two updates' worth of simulated time, never a burst.
        self.clock = SimClock(step_s=1.0 / s.physics_hz, speed=s.speed,
                              max_lag_wall_s=2.0 / s.max_update_hz)
        self._clock_lock = threading.Lock()
        self._now_ns = 0
        try:
            fleet = fleet_spawns(s)
            # one trace per robot (a fleet's in DIR/<robot>/), in the robots' order
            self.traces = [TraceWriter(trace_path(s.trace_file, name), s.trace_period_s)
                           if s.trace_file else None for name, _ in fleet]
        except OSError as exc:
            self.node.destroy_node()
            raise SimConfigError(f"parameter trace_file: cannot write {exc.filename}: "
                                 f"{exc.strerror or exc}") from exc
        except SimConfigError:
            self.node.destroy_node()
            raise
        self.trace = self.traces[0]
        self.robots = [RobotStack(name, spawn, s, self.grid, sim_node=self.node, now_ns=self.now_ns,
                                  listener=functools.partial(self._on_goal_event, i),
                                  event_sink=functools.partial(self._on_request_event, i))
                       for i, (name, spawn) in enumerate(fleet)]
        first = self.robots[0]  # the single robot's parts, by the names they always had
        self.navigator, self.amcl, self.gate = first.navigator, first.amcl, first.gate
        self.costmaps, self.map_server = first.costmaps, first.map_server
        missing = list(dict.fromkeys(take_not_offered()))
        if missing:
            self.node.get_logger().info(
                "Not offered (interface types not installed; the stand-in nav2_msgs has "
                f"NavigateToPose only): {', '.join(missing)}")
        self._time_source = TimeSource()  # no node: fed by the physics loop, no subscription
        self._time_source.ros_time_is_active = True
        for node in self.nodes:
            self._time_source.attach_clock(node.get_clock())
        self._clock_pub = self.node.create_publisher(Clock, "/clock", 10)
        self.lives = [LiveParameters(s.faults, costmaps=robot.costmaps,
                                     navigator=robot.navigator, set_speed=self._set_speed,
                                     log=self.node.get_logger().info if i == 0 else _quiet)
                      for i, robot in enumerate(self.robots)]
        self.live = self.lives[0]
        for live in self.lives:  # every robot takes a run-time fault (all or none: same check)
            self.node.add_on_set_parameters_callback(live.on_set)
        self.node.create_service(Trigger, "~/reset", self._on_reset)
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._physics_loop, name="sim-physics",
                                        daemon=True)
        self._wall_start = 0.0
        self._new_speed: float | None = None
        self._published = threading.Condition()  # the physics loop's last published state:
        self._published_generation = 0  # of this navigator generation (see _on_reset)

    @property
    def nodes(self) -> list[Node]:
        """Every node of the simulator (to add to the executor)."""
        return [self.node, *(node for robot in self.robots for node in robot.nodes)]

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
        """Start the Nav2 nodes up (``autostart``), publish the state, start the physics."""
        s = self.settings
        if s.autostart:
            for robot in self.robots:
                robot.startup()
        self._update_traffic(0.0)
        for robot in self.robots:
            robot.publish_state(0, robot.navigator.state())
        self._clock_pub.publish(Clock())
        for robot, trace in zip(self.robots, self.traces, strict=True):
            if trace is not None:
                spawn = robot.spawn
                trace.event(0.0, "start", x=spawn.x, y=spawn.y, yaw=spawn.yaw, speed=s.speed,
                            map=str(s.map_yaml))
        self._wall_start = time.monotonic()
        self._thread.start()

    def stop(self, reason: str = "simulator shutting down") -> bool:
        """Abort a goal in flight, stop physics, close the trace.

        Args:
            reason: ``error_msg`` of a goal in flight.

        Returns:
            Whether a goal was in flight (keep spinning briefly so its result goes out).
        """
        closed = [robot.gate.close(reason) for robot in self.robots]
        aborted = next((goal for goal in closed if goal is not None), None)
        for goal in closed:
            if goal is not None:
                self.node.get_logger().warning(f"Goal {goal.number} aborted: {reason}")
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
        for robot, trace in zip(self.robots, self.traces, strict=True):
            if trace is not None:
                trace.event(sim_s, "end", path_m=robot.navigator.state().odometry,
                            goals=robot.navigator.accepted_count, wall_s=wall, rtf=rtf,
                            dropped_steps=self.clock.dropped_steps)
                trace.close()
        return aborted is not None

    def destroy(self) -> None:
        """Destroy every node (after the executor has stopped)."""
        for node in self.nodes:
            node.destroy_node()

    def ready_message(self) -> str:
        """The start-up log line (tests and the runner wait for ``ready``)."""
        s = self.settings
        faults = f"; faults: {s.faults.describe()}" if s.faults.any else ""
        return (
            f"ready: Nav2 {'active' if s.autostart else 'unconfigured (autostart off)'}, "
            f"/clock at {s.speed:g}x real time "
            f"(physics {s.physics_hz:g} Hz), map {s.map_yaml} "
            f"({self.grid.width}x{self.grid.height}), {self._spawns()}{faults}"
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
            if any(robot.navigator.planning for robot in self.robots):
                clock.hold()  # a plan takes no simulated time
                self._stop.wait(0.001)
                continue
            wall = time.monotonic()
            steps = clock.due_steps(wall)
            for _ in range(steps):
                now_ns = clock.advance()
                if len(self.robots) > 1:
                    self._update_traffic(now_ns / NS_PER_S)
                for robot in self.robots:
                    robot.navigator.step(dt, now_ns / NS_PER_S)
            if steps:
                now_ns = clock.now_ns
                with self._clock_lock:
                    self._now_ns = now_ns
                clock_msg = Clock(clock=messages.time_msg(now_ns))
                self._time_source.clock_callback(clock_msg)
                self._clock_pub.publish(clock_msg)
                generation = self._generation()  # read before the state it describes
                state = self.navigator.state()
                if now_ns >= next_publish_ns or generation != self._published_generation:
                    for robot in self.robots:
                        robot.publish_state(now_ns, robot.navigator.state())
                        robot.gate.state_published(now_ns)  # results may go out now
                    next_publish_ns = now_ns + publish_period_ns
                    with self._published:
                        self._published_generation = generation
                        self._published.notify_all()
                for robot, trace in zip(self.robots, self.traces, strict=True):
                    if trace is not None:
                        now = state if robot is self.robots[0] else robot.navigator.state()
                        trace.pose(now_ns / NS_PER_S, now.pose.x, now.pose.y, now.pose.yaw,
                                   now.odometry)
            after = time.monotonic()
            pause = max(clock.wall_until_next_step(after), min_period - (after - wall))
            self._stop.wait(pause)

    def _update_traffic(self, now_s: float) -> None:
        """Tell each robot where the others' footprints are (see :mod:`.traffic`)."""
        footprints = [robot.footprint() for robot in self.robots]
        for i, robot in enumerate(self.robots):
            robot.traffic.update(footprints[:i] + footprints[i + 1:], now_s)

    def _spawns(self) -> str:
        """The spawn poses for the ready line."""
        return ", ".join(
            f"{robot.name + ' ' if robot.name else ''}spawn ({robot.spawn.x:.2f}, "
            f"{robot.spawn.y:.2f}, yaw {robot.spawn.yaw:.2f})" for robot in self.robots)

    # ------------------------------------------------------------------ events

    def _on_goal_event(self, index: int, goal: Goal, sim_s: float, robot: RobotState) -> None:
        """Trace robot ``index``'s goal starts and ends (with the navigator's lock held)."""
        trace = self.traces[index]
        if trace is None:
            return
        target = goal.target
        fields: dict[str, Any] = {"goal": goal.number, "x": target.x, "y": target.y,
                                  "yaw": target.yaw, "path_m": robot.odometry}
        if goal.active:
            trace.event(sim_s, "accepted", **fields)
            return
        fields.update(robot_x=robot.pose.x, robot_y=robot.pose.y, robot_yaw=robot.pose.yaw)
        if goal.error_code or goal.error_msg:
            fields.update(error_code=goal.error_code, error_msg=goal.error_msg)
        trace.event(sim_s, goal.outcome.value, **fields)

    def _on_request_event(self, index: int, event: str, **fields: Any) -> None:
        """Trace robot ``index``'s goal requests the navigator never saw (rejections)."""
        trace = self.traces[index]
        if trace is not None:
            trace.event(self.now_ns() / NS_PER_S, event, **fields)

    def _set_speed(self, speed: float) -> None:
        self._new_speed = speed  # applied by the physics thread

    def _generation(self) -> int:
        """Counts resets of every robot (each navigator's count only grows)."""
        return sum(robot.navigator.generation for robot in self.robots)

    def _on_reset(self, _request: Trigger.Request, response: Trigger.Response
                  ) -> Trigger.Response:
        """``~/reset``: abort every goal, robots at rest at spawn, faults re-armed."""
        s = self.settings
        aborted = [robot.navigator.reset(robot.spawn, "simulator reset (~/reset)")
                   for robot in self.robots]
        for robot, live in zip(self.robots, self.lives, strict=True):
            live.rearm()
            robot.amcl.reset(localized=s.auto_localize)
            robot.traffic.refresh()
        with self._published:  # the next physics step publishes TF and odometry at spawn
            self._published.wait_for(
                lambda: self._published_generation == self._generation(), timeout=1.0)
        for robot in self.robots:
            robot.amcl.publish_truth(self.now_ns())
        for robot, trace in zip(self.robots, self.traces, strict=True):
            if trace is not None:
                trace.event(self.now_ns() / NS_PER_S, "reset", x=robot.spawn.x,
                            y=robot.spawn.y, yaw=robot.spawn.yaw)
        what = "".join(f"goal {goal.number} aborted, " for goal in aborted if goal is not None)
        where = "robot at spawn" if len(self.robots) == 1 else "robots at their spawns"
        first = self.robots[0].spawn
        at = f" ({first.x:.2f}, {first.y:.2f})" if len(self.robots) == 1 else ""
        response.success = True
        response.message = (f"reset: {what}{where}{at}, "
                            f"{len(self.live.phantoms)} phantom obstacles in both costmaps, "
                            f"stuck for {self.live.stuck_recoveries} recoveries")
        self.node.get_logger().info(response.message)
        return response


def _quiet(_line: str) -> None:
    """A log that drops its line (the fleet's robots after the first take the same change)."""
