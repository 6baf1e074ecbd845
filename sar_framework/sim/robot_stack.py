"""One simulated robot and its Nav2 stack, in the root namespace or a fleet robot's.

A :class:`RobotStack` is what one Nav2 ``bringup_launch.py`` brings up for one robot: the
drive model and navigator, AMCL, map_server, the servers, their two lifecycle managers,
and the robot's TF and odometry publishers. Outside a fleet (``name`` '') every name is
the one Nav2 uses for a single robot (``/navigate_to_pose``, ``/tf``,
``/odometry/filtered``). In a fleet every node lives under ``/<name>`` and TF goes out on
``/<name>/tf`` with unprefixed frames (``map``, ``odom``, ``base_link``), as nav2_bringup's
multi-robot launch remaps ``/tf`` and ``/tf_static`` to the namespace's ``tf`` and
``tf_static``; odometry on ``/<name>`` + ``odom_topic``.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from nav_msgs.msg import Odometry
from rclpy.node import Node
from rclpy.parameter import Parameter
from tf2_msgs.msg import TFMessage

from sar_framework.sim import messages
from sar_framework.sim.amcl import AmclStandIn
from sar_framework.sim.costmaps import Costmaps
from sar_framework.sim.drive import DiffDrive
from sar_framework.sim.faults import Circle
from sar_framework.sim.goal_actions import GoalGate
from sar_framework.sim.goals import GoalListener, RobotState
from sar_framework.sim.lifecycle import robot_namespace
from sar_framework.sim.lifecycle_manager import LifecycleManager
from sar_framework.sim.map_server import MapServer
from sar_framework.sim.motion_servers import BehaviorServer, ControllerServer, WaypointFollower
from sar_framework.sim.nav_server import BtNavigator
from sar_framework.sim.navigation import Navigator
from sar_framework.sim.occupancy import OccupancyGrid
from sar_framework.sim.planning_servers import PlannerServer, SmootherServer
from sar_framework.sim.settings import SimSettings
from sar_framework.sim.traffic import Traffic
from sar_framework.sim.world import Pose2D

__all__ = ["RobotStack", "topic_in"]


def topic_in(name: str, topic: str) -> str:
    """``topic`` under robot ``name``'s namespace, absolute ('' = the root: unchanged).

    Args:
        name: The robot's namespace without slashes, or ''.
        topic: An absolute or relative topic name (``/tf``, ``odometry/filtered``).
    """
    topic = "/" + topic.lstrip("/")
    return topic if not name else f"/{name}{topic}"


class RobotStack:
    """One robot, its navigator and its Nav2 nodes.

    Args:
        name: The robot's namespace ('' for the single robot of the root namespace).
        spawn: Where it starts.
        settings: The simulator's settings (limits, frames, faults are the fleet's).
        grid: The map.
        sim_node: The simulator's node (the TF and odometry publishers are made on it).
        now_ns: Simulated time.
        listener: Told about goal starts and ends (the trace), or None.
        event_sink: Told about goal requests never started (the trace), or None.
    """

    def __init__(self, name: str, spawn: Pose2D, settings: SimSettings, grid: OccupancyGrid,
                 *, sim_node: Node, now_ns: Callable[[], int],
                 listener: GoalListener | None = None,
                 event_sink: Callable[..., None] | None = None) -> None:
        s = settings
        self.name = name
        self.spawn = spawn
        self.settings = s
        self.traffic = Traffic(s.robot_radius)
        self.costmaps = Costmaps(grid, s.robot_radius, s.faults.phantom_obstacles,
                                 walls=s.faults.blocked_areas, traffic=self.traffic)
        self.navigator = Navigator(DiffDrive(spawn, s.limits), self.costmaps.planner(),
                                   s.faults, listener, costmaps=self.costmaps,
                                   traffic=self.traffic)
        with robot_namespace(name):
            self.amcl = AmclStandIn(lambda: self.navigator.state().pose, now_ns,
                                    global_frame=s.global_frame, localized=s.auto_localize)
            localized = lambda: self.amcl.localized  # noqa: E731 - read at call time
            self.gate = GoalGate(self.navigator, now_ns, 1.0 / s.feedback_hz)
            self.nav = BtNavigator(self.gate, localized, faults=s.faults,
                                   global_frame=s.global_frame, event_sink=event_sink)
            self.map_server = MapServer(grid, s.global_frame, now_ns, str(s.map_yaml))
            self.planner_server = PlannerServer(self.navigator, now_ns, localized,
                                                global_frame=s.global_frame,
                                                resolution=grid.resolution)
            self.smoother_server = SmootherServer(self.navigator.is_free)
            self.controller_server = ControllerServer(self.gate)
            self.behavior_server = BehaviorServer(self.gate)
            self.waypoint_follower = WaypointFollower(self.gate, localized)
            self.managers = [
                LifecycleManager("lifecycle_manager_localization",
                                 [self.map_server, self.amcl.node]),
                LifecycleManager("lifecycle_manager_navigation", [
                    self.controller_server.node, self.smoother_server.node,
                    self.planner_server.node, self.behavior_server.node, self.nav.node,
                    self.waypoint_follower.node]),
            ]
        for manager in self.managers:
            manager.node.set_parameters([Parameter("autostart", value=s.autostart)])
        self._tf_pub = sim_node.create_publisher(TFMessage, topic_in(name, "/tf"), 100)
        self._odom_pub = sim_node.create_publisher(Odometry, topic_in(name, s.odom_topic), 10)
        self._state_msgs = messages.StateMessages(
            spawn, (s.global_frame, s.odom_frame, s.base_frame))

    @property
    def nodes(self) -> list[Any]:
        """Every node of this robot's stack (to add to the executor)."""
        return [self.map_server, self.amcl.node, self.controller_server.node,
                self.controller_server.costmap, self.smoother_server.node,
                self.planner_server.node, self.planner_server.costmap,
                self.behavior_server.node, self.nav.node, self.waypoint_follower.node,
                *(m.node for m in self.managers)]

    def footprint(self) -> Circle:
        """This robot's footprint now, as an obstacle for the others."""
        pose = self.navigator.state().pose
        return Circle(pose.x, pose.y, self.traffic.radius, label=self.name)

    def startup(self) -> None:
        """Start the Nav2 nodes up (``autostart``)."""
        for manager in self.managers:
            manager.startup()

    def publish_state(self, now_ns: int, state: RobotState) -> None:
        """Publish TF and odometry for ``state``; let AMCL update."""
        odom_pose = messages.relative_pose(self.spawn, state.pose)
        self.amcl.on_motion(now_ns)
        tf = self._state_msgs.fill(odom_pose, (state.linear, state.angular), now_ns,
                                   localized=self.amcl.localized)
        self._tf_pub.publish(tf)
        self._odom_pub.publish(self._state_msgs.odometry)
