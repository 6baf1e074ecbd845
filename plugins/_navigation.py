"""NavigateToPoseLeaf: the Nav2 ``NavigateToPose`` client behind NavigateToZone and NavigateToBase.

The guide's pattern: the ``ActionClient`` is created in ``setup()``; ``initialise()`` resets the
``_done``/``_success`` latch and sends the goal; ``update()`` polls the goal and result futures
and never blocks; ``terminate()`` cancels a goal still in flight, and only then. The verdict is
read from the goal status (SUCCEEDED / ABORTED / CANCELED; a rejected goal fails), never from
the result fields, though ``error_msg`` is quoted in a failure message when Nav2 gives one.

Where the guide is silent, nothing waits forever: the action server must be ready within
``server_timeout_s`` (the goal is sent on the first tick it is), and the goal must finish
within ``navigation_timeout_s`` of being sent, otherwise it is cancelled and the leaf fails.
Both bounds count on the node's clock (ROS time: simulated seconds with ``use_sim_time``),
like the tree's ``timeout`` decorators, so the order in which bounds fire does not change
with the simulation's speed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from py_trees.common import Status

from sar_framework.engine.plugin import Param
from sar_framework.events.event import EventKind

from ._ros_leaf import RosLeaf

if TYPE_CHECKING:
    from rclpy.action import ActionClient
    from rclpy.action.client import ClientGoalHandle
    from rclpy.task import Future
    from sar_plugins.sar.zone_manager import ZoneManager

#: The params NavigateToZone and NavigateToBase both declare.
NAVIGATION_PARAMS: tuple[Param, ...] = (
    Param("action_name", str, default="navigate_to_pose",
          description="Name of the Nav2 NavigateToPose action server."),
    Param("frame_id", str, default="map",
          description="Frame of the goal pose (the global frame)."),
    Param("behavior_tree", str, default="",
          description="Nav2 behaviour tree XML for the goal; empty for bt_navigator's default."),
    Param("server_timeout_s", float, default=10.0, exclusive_minimum=0.0,
          description="Fail if the action server is not ready within this many seconds "
                      "(ROS time)."),
    Param("navigation_timeout_s", float, default=300.0, exclusive_minimum=0.0,
          description="Cancel the goal and fail if it has not finished this many seconds "
                      "after it was sent (ROS time)."),
)


@dataclass(frozen=True)
class NavigationTarget:
    """Where one active period navigates to, and what to say about it.

    Attributes:
        label: Names the target in messages (``zone_a``, ``base station``).
        x: Metres in the goal frame.
        y: Metres in the goal frame.
        yaw: Radians about z.
        announce: Logged when the goal is sent.
        reached: Logged when the goal succeeds.
        zone_id: The zone it is ("" for the base station).
    """

    label: str
    x: float
    y: float
    yaw: float
    announce: str
    reached: str
    zone_id: str = ""


def yaw_to_quaternion(yaw: float) -> tuple[float, float, float, float]:
    """Return the ``(x, y, z, w)`` quaternion of a rotation by ``yaw`` radians about z."""
    return 0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0)


class NavigateToPoseLeaf(RosLeaf):
    """Base of the navigation leaves; subclasses only say where to go (:meth:`_target`).

    Args:
        name: The behaviour's name.
        zone_manager: The mission's shared zone state.
        action_name: Nav2 action server name.
        frame_id: Frame of the goal pose.
        behavior_tree: Nav2 BT XML for the goal ("" for the default).
        server_timeout_s: Bound on waiting for the action server.
        navigation_timeout_s: Bound on a goal, from sending to result.
    """

    def __init__(self, name: str, *, zone_manager: ZoneManager,
                 action_name: str = "navigate_to_pose", frame_id: str = "map",
                 behavior_tree: str = "", server_timeout_s: float = 10.0,
                 navigation_timeout_s: float = 300.0) -> None:
        super().__init__(name)
        self.zone_manager = zone_manager
        self.action_name = action_name
        self.frame_id = frame_id
        self.behavior_tree = behavior_tree
        self.server_timeout_s = server_timeout_s
        self.navigation_timeout_s = navigation_timeout_s
        self._client: ActionClient | None = None
        self._action_type: Any = None
        self._target_now: NavigationTarget | None = None
        self._send_future: Future | None = None
        self._goal_handle: ClientGoalHandle | None = None
        self._result_future: Future | None = None
        self._distance_remaining: float | None = None
        self._started = 0.0
        self._sent = 0.0

    def _target(self) -> NavigationTarget:
        """Return where to go now.

        Raises:
            LookupError: There is nowhere to go (the leaf then fails with its message).
        """
        raise NotImplementedError

    def setup(self, **kwargs: Any) -> None:
        """Take the ROS node and create the ``NavigateToPose`` action client.

        Args:
            **kwargs: Must hold ``node``.
        """
        super().setup(**kwargs)
        from nav2_msgs.action import NavigateToPose
        from rclpy.action import ActionClient

        self._action_type = NavigateToPose
        self._client = ActionClient(self.node, NavigateToPose, self.action_name)

    def initialise(self) -> None:
        """Reset the latch and the futures, pick the target and send the goal."""
        self._reset_latch()
        self._send_future = self._goal_handle = self._result_future = None
        self._distance_remaining = None
        self._started = self.now()
        try:
            self._target_now = self._target()
        except LookupError as exc:
            self._target_now = None
            self._latch(False, f"nowhere to navigate: {exc}")
            return
        if self._action_client().server_is_ready():
            self._send_goal()
        else:
            self.feedback_message = f"waiting for the {self.action_name} action server"

    def update(self) -> Status:
        """Poll the goal without blocking.

        Returns:
            RUNNING while waiting for the server or the goal; SUCCESS when the goal
            succeeded; FAILURE when it was rejected, aborted or cancelled, or a bound passed.
        """
        if self._done:
            return self._verdict()
        target = self._target_now
        assert target is not None  # set by initialise() whenever not done
        now = self.now()
        if self._send_future is None and self._goal_handle is None:  # not sent yet
            if self._action_client().server_is_ready():
                self._send_goal()
                return Status.RUNNING
            if now - self._started > self.server_timeout_s:
                return self._latch(False, f"{self.action_name} server not available after "
                                          f"{self.server_timeout_s:.1f} s")
            return Status.RUNNING
        if self._goal_handle is None:
            assert self._send_future is not None
            if not self._send_future.done():
                return self._still_running(target, now)
            future, self._send_future = self._send_future, None
            if future.exception() is not None:
                return self._latch(False, f"goal to {target.label} failed: {future.exception()}")
            handle = future.result()
            if handle is None or not handle.accepted:
                return self._latch(False, f"goal to {target.label} rejected by "
                                          f"{self.action_name}")
            self._goal_handle = handle
            self._result_future = handle.get_result_async()
        assert self._result_future is not None
        if not self._result_future.done():
            return self._still_running(target, now)
        return self._finish(target, self._result_future.result())

    def terminate(self, new_status: Status) -> None:
        """Cancel the goal if it is still in flight (the leaf was halted before a verdict).

        Args:
            new_status: The status the leaf is moving to.
        """
        if self._done or (self._send_future is None and self._goal_handle is None):
            return
        self._cancel_in_flight()
        label = self._target_now.label if self._target_now else "target"
        self.feedback_message = f"navigation to {label} interrupted; goal cancelled"
        self.node.get_logger().info(self.feedback_message)

    def shutdown(self) -> None:
        """Destroy the action client."""
        if self._client is not None:
            self._client.destroy()
            self._client = None

    # -- helpers -------------------------------------------------------------------------

    def _action_client(self) -> ActionClient:
        if self._client is None:
            raise RuntimeError(f"{type(self).__name__} '{self.name}' used before setup(node=...)")
        return self._client

    def _send_goal(self) -> None:
        target = self._target_now
        assert target is not None
        goal = self._action_type.Goal()
        goal.pose.header.frame_id = self.frame_id
        goal.pose.header.stamp = self.node.get_clock().now().to_msg()
        goal.pose.pose.position.x = target.x
        goal.pose.pose.position.y = target.y
        orientation = goal.pose.pose.orientation
        orientation.x, orientation.y, orientation.z, orientation.w = yaw_to_quaternion(target.yaw)
        goal.behavior_tree = self.behavior_tree
        self._send_future = self._action_client().send_goal_async(
            goal, feedback_callback=self._on_feedback
        )
        self._sent = self.now()
        self.feedback_message = f"goal sent: {target.label}"
        self.node.get_logger().info(target.announce)
        self.events.emit(EventKind.NAVIGATION, source=self, zone_id=target.zone_id,
                         message=target.announce, position=(target.x, target.y))

    def _still_running(self, target: NavigationTarget, now: float) -> Status:
        """RUNNING while the goal is within its bound; past it, cancel and fail."""
        if now - self._sent <= self.navigation_timeout_s:
            if self._distance_remaining is not None:
                self.feedback_message = (f"navigating to {target.label}: "
                                         f"{self._distance_remaining:.2f} m remaining")
            return Status.RUNNING
        answered = self._goal_handle is not None
        self._cancel_in_flight()
        if not answered:
            return self._latch(False, f"{self.action_name} did not answer the goal to "
                                      f"{target.label} within {self.navigation_timeout_s:.1f} s")
        return self._latch(False, f"navigation to {target.label} not finished within "
                                  f"{self.navigation_timeout_s:.1f} s; goal cancelled")

    def _reached(self, target: NavigationTarget) -> None:
        """Called when the goal to ``target`` succeeded (before the verdict)."""

    def _on_feedback(self, message: Any) -> None:
        self._distance_remaining = float(message.feedback.distance_remaining)

    def _finish(self, target: NavigationTarget, response: Any) -> Status:
        from action_msgs.msg import GoalStatus

        self._result_future = None
        self._goal_handle = None
        status = getattr(response, "status", GoalStatus.STATUS_UNKNOWN)
        error_msg = getattr(getattr(response, "result", None), "error_msg", "")
        detail = f": {error_msg}" if error_msg else ""
        if status == GoalStatus.STATUS_SUCCEEDED:
            self._reached(target)
            return self._latch(True, target.reached)
        if status == GoalStatus.STATUS_ABORTED:
            return self._latch(False, f"goal to {target.label} aborted{detail}")
        if status == GoalStatus.STATUS_CANCELED:
            return self._latch(False, f"goal to {target.label} cancelled{detail}")
        return self._latch(False, f"goal to {target.label} ended with status {status}{detail}")

    def _cancel_in_flight(self) -> None:
        """Ask the server to cancel the current goal, now or as soon as it is accepted."""
        if self._goal_handle is not None:
            self._goal_handle.cancel_goal_async()
        elif self._send_future is not None:
            self._send_future.add_done_callback(_cancel_if_accepted)
        self._send_future = self._goal_handle = self._result_future = None


def _cancel_if_accepted(future: Future) -> None:
    """Cancel a goal whose acceptance arrives after the leaf stopped wanting it."""
    if future.exception() is None and future.result() is not None and future.result().accepted:
        future.result().cancel_goal_async()
