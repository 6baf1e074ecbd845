"""Static transform broadcasting: ``tf2_ros`` when installed, an equivalent publisher otherwise.

This is the one place that makes the choice. ``tf2_ros`` is not on PyPI, so without a
ROS installation :class:`TopicStaticBroadcaster` stands in for
``tf2_ros.StaticTransformBroadcaster`` with the same observable behaviour (Jazzy's
``tf2_ros_py``): it publishes ``tf2_msgs/msg/TFMessage`` on ``/tf_static`` (RELIABLE,
TRANSIENT_LOCAL, depth 1) and every message carries *all* frames sent so far, one per child
frame, in first-sent order; a transform for a child frame already sent is ignored (the first
one stays), though the message is published again. With depth 1 a subscriber that joins
late receives exactly one message holding every frame (``ros2 topic echo /tf_static --once``).
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING, Protocol

from sar_framework.ros.qos import tf_static_broadcaster_qos

if TYPE_CHECKING:
    from geometry_msgs.msg import TransformStamped
    from rclpy.node import Node

#: The topic tf2_ros latches static transforms on.
TF_STATIC_TOPIC = "/tf_static"


class StaticBroadcaster(Protocol):
    """What callers may rely on: tf2_ros's ``sendTransform``."""

    def sendTransform(  # noqa: N802 - tf2_ros's method name
        self, transform: TransformStamped | Iterable[TransformStamped]
    ) -> None:
        """Broadcast one transform or several."""


class TopicStaticBroadcaster:
    """A ``tf2_ros.StaticTransformBroadcaster`` stand-in built on a plain publisher.

    Args:
        node: The node that owns the publisher.
        topic: Where to publish; ``/tf_static`` unless testing.
    """

    def __init__(self, node: Node, topic: str = TF_STATIC_TOPIC) -> None:
        from tf2_msgs.msg import TFMessage

        self._message_type = TFMessage
        self._publisher = node.create_publisher(TFMessage, topic, tf_static_broadcaster_qos())
        # child_frame_id -> the first transform sent for it; dicts keep insertion order.
        self._frames: dict[str, TransformStamped] = {}

    def sendTransform(  # noqa: N802 - tf2_ros's method name
        self, transform: TransformStamped | Iterable[TransformStamped]
    ) -> None:
        """Add new child frames (repeats are ignored) and publish every frame in one message.

        Args:
            transform: A ``geometry_msgs/msg/TransformStamped`` or an iterable of them.
        """
        batch = [transform] if hasattr(transform, "child_frame_id") else list(transform)
        for item in batch:
            self._frames.setdefault(item.child_frame_id, item)
        self._publisher.publish(self._message_type(transforms=list(self._frames.values())))

    def frames(self) -> list[str]:
        """Return the child frame ids broadcast so far, in first-sent order."""
        return list(self._frames)


def make_static_broadcaster(node: Node) -> StaticBroadcaster:
    """Return ``tf2_ros.StaticTransformBroadcaster(node)`` if tf2_ros imports, else the stand-in.

    Args:
        node: The node that owns the broadcaster.
    """
    try:
        from tf2_ros import StaticTransformBroadcaster
    except ImportError:
        return TopicStaticBroadcaster(node)
    return StaticTransformBroadcaster(node)
