"""The robot's pose, speed and goal updates from a ROS node, for Nav2's robot-aware decorators.

:func:`robot_context` returns the build-context entries of
:mod:`sar_plugins.nav2.robot_context` for a node. Each source subscribes when it is
started (when a tree node that reads it is built), so a tree without those decorators
costs nothing:

- pose: TF ``global_frame -> robot_base_frame`` (a ``tf2_ros`` buffer; frames default to
  the node's ``global_frame`` / ``robot_base_frame`` parameters, else ``map`` /
  ``base_link``); None without tf2_ros or the transform;
- speed: planar speed of the last ``nav_msgs/Odometry`` on the node's ``odom_topic``
  parameter, else ``odom``;
- goal update: the last ``geometry_msgs/PoseStamped`` on ``goal_update`` (Nav2's topic).
"""

from __future__ import annotations

import math
from typing import Any

from sar_plugins.nav2.robot_context import (
    GOAL_UPDATE_KEY,
    ROBOT_POSE_KEY,
    ROBOT_SPEED_KEY,
)


def _setting(node: Any, name: str, default: str) -> str:
    if node.has_parameter(name):
        value = node.get_parameter(name).value
        if value:
            return str(value)
    return default


class PoseSource:
    """``pose(global_frame, robot_base_frame) -> (x, y) | None`` from TF.

    Args:
        node: The node whose subscriptions feed TF.
    """

    def __init__(self, node: Any) -> None:
        self.node = node
        self.buffer: Any = None
        self._listener: Any = None

    def start(self) -> None:
        """Start listening to TF (once)."""
        if self._listener is not None:
            return
        try:
            from tf2_ros import Buffer, TransformListener
        except ImportError:
            return
        self.buffer = Buffer()
        self._listener = TransformListener(self.buffer, self.node)

    def __call__(self, global_frame: str, robot_base_frame: str) -> tuple[float, float] | None:
        """The robot's (x, y) in ``global_frame``, or None."""
        if self.buffer is None:
            return None
        from rclpy.time import Time

        frame = global_frame or _setting(self.node, "global_frame", "map")
        base = robot_base_frame or _setting(self.node, "robot_base_frame", "base_link")
        try:
            t = self.buffer.lookup_transform(frame, base, Time()).transform.translation
        except Exception:  # tf2's lookup and extrapolation errors
            return None
        return t.x, t.y


class LastMessage:
    """The last message on a topic (subscribed when started).

    Args:
        node: The subscribing node.
        kind: ``"odometry"`` (returns the planar speed) or ``"goal"`` (the message).
    """

    def __init__(self, node: Any, kind: str) -> None:
        self.node = node
        self.kind = kind
        self.last: Any = None
        self._subscription: Any = None

    def start(self) -> None:
        """Subscribe (once)."""
        if self._subscription is not None:
            return
        if self.kind == "odometry":
            from nav_msgs.msg import Odometry

            topic, msg_type = _setting(self.node, "odom_topic", "odom"), Odometry
        else:
            from geometry_msgs.msg import PoseStamped

            topic, msg_type = "goal_update", PoseStamped
        self._subscription = self.node.create_subscription(msg_type, topic, self._keep, 10)

    def _keep(self, message: Any) -> None:
        self.last = message

    def __call__(self) -> Any:
        """The speed (odometry) or the message (goal); None before the first."""
        if self.last is None or self.kind != "odometry":
            return self.last
        linear = self.last.twist.twist.linear
        return math.hypot(linear.x, linear.y)


def robot_context(node: Any) -> dict[str, Any]:
    """The build-context entries for ``node``: pose, speed and goal-update sources."""
    return {ROBOT_POSE_KEY: PoseSource(node), ROBOT_SPEED_KEY: LastMessage(node, "odometry"),
            GOAL_UPDATE_KEY: LastMessage(node, "goal")}
