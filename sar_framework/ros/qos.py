"""QoS profiles the mission's ROS interfaces agree on.

Functions rather than module constants, because :class:`rclpy.qos.QoSProfile`
is mutable and each caller should get its own copy.
"""

from __future__ import annotations

from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

#: Depth of tf2_ros's ``/tf_static`` listener (``StaticListenerQoS``).
TF_STATIC_DEPTH = 100
#: Depth of tf2_ros's ``StaticTransformBroadcaster`` publisher: each message carries every
#: frame, so a late subscriber gets exactly one message, the complete one.
TF_STATIC_BROADCASTER_DEPTH = 1


def tf_static_qos() -> QoSProfile:
    """Return the ``/tf_static`` listener profile: RELIABLE, TRANSIENT_LOCAL, keep last 100.

    This is what tf2_ros's ``TransformListener`` subscribes with, so a subscriber that
    joins late still receives the frames.
    """
    return latched_qos(TF_STATIC_DEPTH)


def tf_static_broadcaster_qos() -> QoSProfile:
    """Return ``tf2_ros.StaticTransformBroadcaster``'s profile: RELIABLE, TRANSIENT_LOCAL, 1."""
    return latched_qos(TF_STATIC_BROADCASTER_DEPTH)


def latched_qos(depth: int = 1) -> QoSProfile:
    """Return a "latched" profile: RELIABLE, TRANSIENT_LOCAL, keep last ``depth``.

    Used for topics whose last message a late subscriber must still get, such as
    ``/amcl_pose`` and ``/map``.

    Args:
        depth: How many past messages the publisher keeps for late joiners.
    """
    return QoSProfile(
        history=HistoryPolicy.KEEP_LAST,
        depth=depth,
        reliability=ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.TRANSIENT_LOCAL,
    )
