"""Topic leaves: a publisher action and a subscriber condition, QoS from the declaration.

On the semantics of BehaviorTree.ROS2's ``RosTopicPubNode`` and ``RosTopicSubNode``:

* :class:`PublisherLeaf` publishes one message per tick, filled by
  :meth:`PublisherLeaf.set_message` (False: FAILURE, nothing published), and succeeds;
* :class:`TopicCondition` keeps the newest message of its topic and answers in the tick,
  through :meth:`TopicCondition.check` (given None before any message arrived).

The QoS is the leaf's declaration: the params :func:`topic_params` declares (``topic``,
``qos_depth``, ``qos_reliable``, ``qos_latched``), so a tree may change each and the
checker knows them before the run. Imports no ROS package at import.
"""

from __future__ import annotations

from typing import Any, ClassVar

from py_trees.common import Status

from sar_framework.engine.param import Param
from sar_framework.leaves.declared import interface_type
from sar_framework.leaves.ros_leaf import RosLeaf


def topic_params(topic: str, *, depth: int = 10, reliable: bool = True,
                 latched: bool = False) -> tuple[Param, ...]:
    """The params a topic leaf reads: the topic and its QoS.

    Args:
        topic: The default topic (relative names resolve in the node's namespace).
        depth: The default history depth.
        reliable: Whether the default reliability is RELIABLE (else BEST_EFFORT).
        latched: Whether the default durability is TRANSIENT_LOCAL (a late subscriber gets
            the last messages) rather than VOLATILE.

    Returns:
        ``topic``, ``qos_depth``, ``qos_reliable`` and ``qos_latched``.
    """
    return (
        Param("topic", str, default=topic, description="The topic."),
        Param("qos_depth", int, default=depth, minimum=1, description="QoS history depth."),
        Param("qos_reliable", bool, default=reliable,
              description="QoS reliability: RELIABLE (true) or BEST_EFFORT (false)."),
        Param("qos_latched", bool, default=latched,
              description="QoS durability: TRANSIENT_LOCAL (true) or VOLATILE (false)."),
    )


def qos_of(leaf: Any) -> Any:
    """The ``QoSProfile`` a topic leaf declared (``qos_depth``, ``qos_reliable``, ...)."""
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

    return QoSProfile(
        depth=int(leaf.qos_depth),
        reliability=(ReliabilityPolicy.RELIABLE if leaf.qos_reliable
                     else ReliabilityPolicy.BEST_EFFORT),
        durability=(DurabilityPolicy.TRANSIENT_LOCAL if leaf.qos_latched
                    else DurabilityPolicy.VOLATILE),
    )


class _TopicLeaf(RosLeaf):
    """What both topic leaves hold: the message type and the declared QoS."""

    #: The message type as ``ros2 interface`` names it (``std_msgs/msg/String``).
    message_type: ClassVar[str] = ""

    def __init__(self, name: str, **declared: Any) -> None:
        self.topic = ""
        self.qos_depth = 10
        self.qos_reliable = True
        self.qos_latched = False
        super().__init__(name, **declared)
        self._type: Any = None

    def setup(self, **kwargs: Any) -> None:
        """Take the ROS node and resolve the message type.

        Args:
            **kwargs: Must hold ``node``; may hold ``events``.
        """
        super().setup(**kwargs)
        self._type = interface_type(self.message_type)


class PublisherLeaf(_TopicLeaf):
    """Publish one message per tick on ``topic``; SUCCESS once published.

    Args:
        name: The behaviour's name.
        **declared: :func:`topic_params` and the leaf's own params, context objects, ports.
    """

    def __init__(self, name: str, **declared: Any) -> None:
        super().__init__(name, **declared)
        self._publisher: Any = None

    def set_message(self, message: Any) -> bool | None:
        """Fill ``message`` (a fresh message); False fails without publishing."""
        return None

    def setup(self, **kwargs: Any) -> None:
        """Create the publisher with the declared QoS.

        Args:
            **kwargs: Must hold ``node``.
        """
        super().setup(**kwargs)
        self._publisher = self.node.create_publisher(self._type, self.topic, qos_of(self))

    def update(self) -> Status:
        """Fill and publish the message.

        Returns:
            SUCCESS once published; FAILURE when :meth:`set_message` refused.
        """
        message = self._type()
        if self.set_message(message) is False:
            self.feedback_message = self.feedback_message or f"nothing to publish on {self.topic}"
            return Status.FAILURE
        self._publisher.publish(message)
        self.feedback_message = f"published on {self.topic}"
        return Status.SUCCESS

    def shutdown(self) -> None:
        """Destroy the publisher."""
        if self._publisher is not None:
            self.node.destroy_publisher(self._publisher)
            self._publisher = None


class TopicCondition(_TopicLeaf):
    """A condition on the newest message of ``topic``: SUCCESS or FAILURE in the tick.

    Args:
        name: The behaviour's name.
        **declared: :func:`topic_params` and the leaf's own params, context objects, ports.
    """

    def __init__(self, name: str, **declared: Any) -> None:
        super().__init__(name, **declared)
        self.last_message: Any = None
        self._subscription: Any = None

    def check(self, message: Any) -> bool:
        """Whether the condition holds; the default: a message has arrived.

        Args:
            message: The newest message, or None before the first.
        """
        return message is not None

    def setup(self, **kwargs: Any) -> None:
        """Subscribe with the declared QoS.

        Args:
            **kwargs: Must hold ``node``.
        """
        super().setup(**kwargs)
        self._subscription = self.node.create_subscription(
            self._type, self.topic, self._keep, qos_of(self))

    def update(self) -> Status:
        """Answer in the tick.

        Returns:
            SUCCESS when :meth:`check` holds on the newest message, else FAILURE.
        """
        self.feedback_message = ("" if self.last_message is not None
                                 else f"no message yet on {self.topic}")
        held = self.check(self.last_message)  # may say more in feedback_message
        return Status.SUCCESS if held else Status.FAILURE

    def shutdown(self) -> None:
        """Destroy the subscription."""
        if self._subscription is not None:
            self.node.destroy_subscription(self._subscription)
            self._subscription = None

    def _keep(self, message: Any) -> None:
        self.last_message = message
