"""The mission's event stream on ROS: ``sar_mission/events`` (``sar_interfaces/msg/MissionEvent``).

The name is relative: ``/sar_mission/events`` in the root namespace, and
``/robot1/sar_mission/events`` for a runner started in ``/robot1`` (a fleet, docs/how-to/fleet.md).

QoS (:func:`event_qos`): RELIABLE, TRANSIENT_LOCAL, KEEP_LAST :data:`EVENT_HISTORY_DEPTH`.
Reliable because a reader decides on every event (a lost ``completion`` is a lost
verdict); transient-local with a deep history so a reader that joins late (``sar-tree
watch``, the recorder started after the runner, a studio) still receives the mission's
events so far: a mission emits tens of events per goal, so 1000 hold a long mission
whole. A subscriber must ask for the same profile to get the past.

:func:`to_message` and :func:`from_message` convert between the ROS message and the
ROS-free :class:`~sar_framework.events.event.MissionEvent`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from sar_framework.events.event import (
    EVENT_TOPIC,
    EVENT_TOPIC_NAME,
    MissionEvent,
    event_kind,
    kind_name,
)

if TYPE_CHECKING:
    from rclpy.node import Node
    from rclpy.qos import QoSProfile

__all__ = ["EVENT_HISTORY_DEPTH", "EVENT_TOPIC", "EVENT_TOPIC_NAME", "EventPublisher",
           "event_qos", "from_message", "to_message"]

EVENT_HISTORY_DEPTH = 1000
"""Events the publisher keeps for late joiners."""
_NS = 1_000_000_000


def event_qos() -> QoSProfile:
    """RELIABLE, TRANSIENT_LOCAL, keep last :data:`EVENT_HISTORY_DEPTH` (see the module)."""
    from sar_framework.ros.qos import latched_qos

    return latched_qos(EVENT_HISTORY_DEPTH)


def to_message(event: MissionEvent) -> Any:
    """The ``sar_interfaces/msg/MissionEvent`` of ``event``."""
    from diagnostic_msgs.msg import KeyValue
    from sar_interfaces.msg import MissionEvent as EventMsg

    message = EventMsg()
    stamp_ns = round(event.sim_s * _NS)
    message.stamp.sec, message.stamp.nanosec = divmod(stamp_ns, _NS)
    message.wall_s = float(event.wall_s)
    message.seq = event.seq
    message.kind = kind_name(event.kind)
    message.node_name = event.node_name
    message.node_uid = event.node_uid
    message.node_kind = event.node_kind
    message.status = event.status
    message.message = event.message
    message.fields = [KeyValue(key=key, value=value) for key, value in event.fields.items()]
    message.has_position = event.position is not None
    if event.position is not None:
        message.position.x, message.position.y, message.position.z = event.position
    return message


def from_message(message: Any) -> MissionEvent:
    """The event a ``sar_interfaces/msg/MissionEvent`` carries.

    Raises:
        ValueError: Its ``kind`` is not a kind name.
    """
    point = message.position
    return MissionEvent(
        kind=event_kind(message.kind), seq=int(message.seq),
        sim_s=round(message.stamp.sec + message.stamp.nanosec / _NS, 9),
        wall_s=float(message.wall_s), node_name=message.node_name,
        node_uid=message.node_uid, node_kind=message.node_kind, status=message.status,
        message=message.message,
        position=(point.x, point.y, point.z) if message.has_position else None,
        fields={pair.key: pair.value for pair in message.fields},
    )


class EventPublisher:
    """Publishes every event it is given on :data:`EVENT_TOPIC_NAME`, relative (an event sink).

    Args:
        node: The node to publish from (the runner's).
    """

    def __init__(self, node: Node) -> None:
        from sar_interfaces.msg import MissionEvent as EventMsg

        self._publisher = node.create_publisher(EventMsg, EVENT_TOPIC_NAME, event_qos())

    def __call__(self, event: MissionEvent) -> None:
        """Publish ``event``."""
        self._publisher.publish(to_message(event))
