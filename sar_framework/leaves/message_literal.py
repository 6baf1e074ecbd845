"""A message literal of a tree file made into the ROS message a leaf reads.

The engine keeps a message-typed port's literal as plain data
(:class:`~sar_framework.engine.message_literals.MessageLiteral`); a toolkit ROS leaf reads
it as the message itself: :meth:`~sar_framework.leaves.RosLeaf.setup` has its ports build
it with :func:`to_message` on every read, so a stamp left as ``now`` is the node's clock at
the moment the leaf reads the port (when it sends the goal). Imports no ROS package at
import.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from sar_framework.leaves.declared import interface_type

if TYPE_CHECKING:
    from rclpy.clock import Clock

    from sar_framework.engine.message_literals import MessageLiteral


def to_message(literal: MessageLiteral, clock: Clock | None = None) -> Any:
    """The ROS message of a literal, its ``now`` stamps read from ``clock``.

    Args:
        literal: The literal (its type and the fields it sets).
        clock: The node's clock; without one a ``now`` stamp is zero.

    Returns:
        A new message of ``literal.type``.
    """
    from rosidl_runtime_py.set_message import set_message_fields

    message = interface_type(literal.type)()
    setters = set_message_fields(message, literal.fields, expand_time_now=True)
    if setters:
        from builtin_interfaces.msg import Time

        now = clock.now().to_msg() if clock is not None else Time()
        for set_stamp in setters:
            set_stamp(now)
    return message
