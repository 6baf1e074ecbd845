"""NavigateToTarget: the NavigateToPose action leaf behind NavigateToZone and NavigateToBase.

An :class:`~sar_framework.leaves.ActionLeaf` of ``nav2_msgs/action/NavigateToPose`` whose
subclasses only say where to go (:meth:`NavigateToTarget.target`) and what reaching it means
(:meth:`NavigateToTarget.reached`). The verdict is read from the goal status (SUCCEEDED /
ABORTED / CANCELED; a rejected goal fails), never from the result fields, though
``error_msg`` is quoted in a failure message when Nav2 gives one. ``server_timeout_s`` bounds
the wait for the server, ``navigation_timeout_s`` the goal from its sending to its result
(the toolkit's ``result_timeout_s``), both on the node's clock. A goal the server has not
accepted within :data:`ACCEPTANCE_WALL_S` is sent once more, then the leaf fails: a request or
answer lost in transport (a server that has not yet matched a new client's reader) costs
seconds, not the mission.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from py_trees.common import Status

from sar_framework.engine.plugin import Param
from sar_framework.events.event import EventKind
from sar_framework.leaves import (
    STATUS_ABORTED,
    STATUS_CANCELED,
    STATUS_SUCCEEDED,
    ActionLeaf,
    GoalFailure,
)

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

ACCEPTANCE_WALL_S = 5.0
"""Wall seconds Nav2 gets to accept a goal (a transport round trip; milliseconds when well)."""


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


class NavigateToTarget(ActionLeaf):
    """Base of the navigation leaves; subclasses say where to go (:meth:`target`).

    Args:
        name: The behaviour's name.
        **declared: :data:`NAVIGATION_PARAMS` and ``zone_manager``.
    """

    action_type = "nav2_msgs/action/NavigateToPose"

    def __init__(self, name: str, **declared: Any) -> None:
        super().__init__(name, **declared)
        self.result_timeout_s = self.navigation_timeout_s
        self.ack_timeout_wall_s = ACCEPTANCE_WALL_S
        self.ack_resends = 1
        self.now_target: NavigationTarget | None = None

    def target(self) -> NavigationTarget:
        """Return where to go now.

        Raises:
            LookupError: There is nowhere to go (the leaf then fails with its message).
        """
        raise NotImplementedError

    def reached(self, target: NavigationTarget) -> None:
        """Called when the goal to ``target`` succeeded (before the verdict)."""

    def initialise(self) -> None:
        """Start a goal period and pick the target (FAILURE when there is none)."""
        super().initialise()
        try:
            self.now_target = self.target()
        except LookupError as exc:
            self.now_target = None
            self.fail(f"nowhere to navigate: {exc}")

    def set_goal(self, goal: Any) -> None:
        """The target's pose, stamped now, in ``frame_id``."""
        target = self._target()
        goal.pose.header.frame_id = self.frame_id
        goal.pose.header.stamp = self.node.get_clock().now().to_msg()
        goal.pose.pose.position.x, goal.pose.pose.position.y = target.x, target.y
        q = goal.pose.pose.orientation
        q.x, q.y, q.z, q.w = yaw_to_quaternion(target.yaw)
        goal.behavior_tree = self.behavior_tree

    def on_sent(self) -> None:
        """Announce the goal: the log line and the ``navigation`` event."""
        target = self._target()
        self.feedback_message = f"goal sent: {target.label}"
        self.node.get_logger().info(target.announce)
        self.events.emit(EventKind.NAVIGATION, source=self, zone_id=target.zone_id,
                         message=target.announce, position=(target.x, target.y))

    def on_feedback(self, feedback: Any) -> None:
        """Say how far the target still is."""
        if feedback is not None:
            self.feedback_message = (f"navigating to {self._target().label}: "
                                     f"{float(feedback.distance_remaining):.2f} m remaining")

    def on_result(self, status: int, result: Any) -> Status:
        """SUCCESS when the goal succeeded (the target is reached), FAILURE otherwise."""
        target = self._target()
        detail = getattr(result, "error_msg", "")
        detail = f": {detail}" if detail else ""
        if status == STATUS_SUCCEEDED:
            self.reached(target)
            return self.latch(True, target.reached)
        ended = {STATUS_ABORTED: "aborted", STATUS_CANCELED: "cancelled"}.get(
            status, f"ended with status {status}")
        return self.fail(f"goal to {target.label} {ended}{detail}")

    def on_failure(self, failure: GoalFailure, reason: str) -> Status:
        """Name the target in the reason of a goal without a result."""
        label, bound = self._target().label, self.navigation_timeout_s
        if failure == GoalFailure.GOAL_REJECTED:
            reason = f"goal to {label} rejected by {self.action_name}"
        elif failure == GoalFailure.SEND_GOAL_TIMEOUT:
            reason = f"goal to {label}: {reason}"
        elif failure == GoalFailure.RESULT_TIMEOUT:
            reason = f"navigation to {label} not finished within {bound:.1f} s; goal cancelled"
        return self.fail(reason)

    def on_halted(self) -> None:
        """Say that the navigation was interrupted."""
        label = self.now_target.label if self.now_target else "target"
        self.feedback_message = f"navigation to {label} interrupted; goal cancelled"
        self.node.get_logger().info(self.feedback_message)

    def _target(self) -> NavigationTarget:
        assert self.now_target is not None  # set by initialise() whenever not done
        return self.now_target
