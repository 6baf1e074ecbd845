"""QoS profiles the mission's ROS interfaces agree on.

Functions rather than module constants, because :class:`rclpy.qos.QoSProfile`
is mutable and each caller should get its own copy.
"""

from __future__ import annotations

from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

#: Depth tf2_ros uses for ``/tf_static``.
TF_STATIC_DEPTH = 100


def tf_static_qos() -> QoSProfile:
    """Return the ``/tf_static`` profile: RELIABLE, TRANSIENT_LOCAL, keep last 100.

    This is what ``tf2_ros.StaticTransformBroadcaster`` and its listeners use, so a
    subscriber that joins late still receives the frames.
    """
    return QoSProfile(
        history=HistoryPolicy.KEEP_LAST,
        depth=TF_STATIC_DEPTH,
        reliability=ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.TRANSIENT_LOCAL,
    )


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
