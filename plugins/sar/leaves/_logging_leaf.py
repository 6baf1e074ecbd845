"""LoggingLeaf: the base of leaves whose work is saying one line.

The line goes to the log and, as a ``note`` event, to the mission's event stream (what
``sar-tree run`` shows).

Not a plugin itself (it carries no ``@leaf`` mark), and it imports no ROS package.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import py_trees

from sar_framework.events.emitter import NO_EVENTS, EventEmitter, events_from
from sar_framework.events.event import EventKind

if TYPE_CHECKING:
    from rclpy.node import Node


class LoggingLeaf(py_trees.behaviour.Behaviour):
    """A leaf that logs to the ROS node's logger when ``setup(node=...)`` gave one.

    Without a node (a tree ticked outside ROS) the line goes to the py_trees logger.

    Args:
        name: The behaviour's name.
    """

    def __init__(self, name: str) -> None:
        super().__init__(name=name)
        self._node: Node | None = None
        self._events: EventEmitter = NO_EVENTS

    def setup(self, **kwargs: Any) -> None:
        """Keep the ROS node, if any, for logging, and the event emitter, if any.

        Args:
            **kwargs: May hold ``node`` and ``events``.
        """
        self._node = kwargs.get("node")
        self._events = events_from(kwargs)

    def say(self, line: str, *, warning: bool = False) -> None:
        """Make ``line`` the feedback message, emit it as a ``note`` and log it.

        Args:
            line: What to say.
            warning: Log as a warning instead of info.
        """
        self.feedback_message = line
        self._events.emit(EventKind.NOTE, source=self, status="WARN" if warning else "",
                          message=line)
        logger = self._node.get_logger() if self._node is not None else self.logger
        if warning:
            logger.warning(line)
        else:
            logger.info(line)
