"""The robot's pose from TF, as Nav2's ``nav2_util::getCurrentPose`` gives it.

One ``tf2_ros.Buffer`` and ``TransformListener`` per ROS node, made on first use and
shared by every leaf set up on that node (Nav2 shares one ``tf_buffer`` the same way).
"""

from __future__ import annotations

from typing import Any

_buffers: dict[int, tuple[Any, Any, Any]] = {}


def tf_buffer(node: Any) -> Any:
    """The node's shared ``tf2_ros.Buffer`` (with its listener)."""
    held = _buffers.get(id(node))
    if held is None or held[0] is not node:
        from tf2_ros import Buffer, TransformListener

        buffer = Buffer()
        held = _buffers[id(node)] = (node, buffer, TransformListener(buffer, node))
    return held[1]


def robot_pose(node: Any, global_frame: str, base_frame: str) -> Any | None:
    """The robot's pose as a ``PoseStamped`` in ``global_frame``; None when TF has none."""
    from geometry_msgs.msg import PoseStamped
    from rclpy.time import Time

    try:
        transform = tf_buffer(node).lookup_transform(global_frame, base_frame, Time())
    except Exception as exc:  # tf2's LookupException, ExtrapolationException, ...
        node.get_logger().debug(f"no robot pose in {global_frame}: {exc}")
        return None
    pose = PoseStamped()
    pose.header = transform.header
    t = transform.transform
    pose.pose.position.x, pose.pose.position.y, pose.pose.position.z = (
        t.translation.x, t.translation.y, t.translation.z)
    pose.pose.orientation = t.rotation
    return pose
