"""RosLeaf: the base of leaves that talk to ROS and latch their verdict.

It holds what every such leaf shares:

* the ROS node, which arrives the py_trees_ros way, ``setup(node=...)``, and the
  runner's event emitter beside it (``setup(events=...)``, :attr:`RosLeaf.events`): what
  a leaf tells other processes goes there, its log lines are for humans;
* the ``_done`` / ``_success`` terminal latch of the implementation guide: reset in
  ``initialise()``, written together exactly once per active period by :meth:`latch`,
  read first in ``update()`` through :meth:`verdict`;
* its declared params and context objects, kept as attributes of the same names;
* its ports' message literals, read as messages (:mod:`.message_literal`).

Not a plugin itself (it carries no ``@leaf`` mark), and it imports no ROS package.
"""

from __future__ import annotations

from functools import partial
from typing import TYPE_CHECKING, Any

import py_trees
from py_trees.common import Status

from sar_framework.events.emitter import NO_EVENTS, EventEmitter, events_from
from sar_framework.leaves.declared import keep_declared
from sar_framework.leaves.message_literal import to_message

if TYPE_CHECKING:
    from rclpy.node import Node


class RosLeaf(py_trees.behaviour.Behaviour):
    """A behaviour with a ROS node and a terminal latch.

    Args:
        name: The behaviour's name.
        **declared: The declared params, context objects and ``ports``, kept as
            attributes of the same names.
    """

    def __init__(self, name: str, **declared: Any) -> None:
        super().__init__(name=name)
        self._node: Node | None = None
        self.events: EventEmitter = NO_EVENTS
        self._done = False
        self._success = False
        keep_declared(self, declared)

    def setup(self, **kwargs: Any) -> None:
        """Take the ROS node from ``kwargs["node"]`` and the event emitter, if any.

        From then on a message literal bound to a port is read as the message, its ``now``
        stamps on the node's clock.

        Args:
            **kwargs: Must hold ``node``, an ``rclpy.node.Node``; may hold ``events``.

        Raises:
            KeyError: Without a node.
        """
        node = kwargs.get("node")
        if node is None:
            raise KeyError(
                f"{type(self).__name__} '{self.name}' needs a ROS node: call setup(node=...)"
            )
        self._node = node
        self.events = events_from(kwargs)
        read_messages_with = getattr(getattr(self, "ports", None), "read_messages_with", None)
        if read_messages_with is not None:
            read_messages_with(partial(to_message, clock=node.get_clock()))

    @property
    def node(self) -> Node:
        """The ROS node given to ``setup()``.

        Raises:
            RuntimeError: Before ``setup()``.
        """
        if self._node is None:
            raise RuntimeError(f"{type(self).__name__} '{self.name}' used before setup(node=...)")
        return self._node

    def now(self) -> float:
        """The node's clock in seconds: ROS time (``/clock`` time with ``use_sim_time``).

        Every bound a leaf declares (``navigation_timeout_s``, ``server_timeout_s``,
        ``response_timeout_s``...) counts on it, like the tree's ``timeout`` decorators.
        """
        return self.node.get_clock().now().nanoseconds / 1e9

    def reset_latch(self) -> None:
        """Forget the previous verdict; call first in ``initialise()``."""
        self._done = False
        self._success = False

    def latch(self, success: bool, message: str, *, log: bool = True) -> Status:
        """Record the verdict of this active period and return it.

        Args:
            success: Whether the leaf succeeded.
            message: Why; becomes ``feedback_message``.
            log: Whether to log ``message`` on the node's logger (info: the runner logs
                a failure's reason line as a warning, with the node's name and uid).

        Returns:
            SUCCESS or FAILURE.
        """
        self._done = True
        self._success = success
        self.feedback_message = message
        if log and self._node is not None:
            self._node.get_logger().info(message)
        return self.verdict()

    def succeed(self, message: str, *, log: bool = False) -> Status:
        """Latch SUCCESS with ``message`` as ``feedback_message`` and return it.

        Args:
            message: What was achieved.
            log: Whether to log it too (a success is quiet by default).
        """
        return self.latch(True, message, log=log)

    def fail(self, message: str) -> Status:
        """Latch FAILURE with ``message`` (logged, and kept in ``feedback_message``).

        Args:
            message: Why the leaf failed.
        """
        return self.latch(False, message)

    def verdict(self) -> Status:
        """Return the latched status: SUCCESS or FAILURE once done, RUNNING before."""
        if not self._done:
            return Status.RUNNING
        return Status.SUCCESS if self._success else Status.FAILURE
