"""Log: say a line at a level, in the log and in the mission's event stream."""

from __future__ import annotations

from typing import Any

import py_trees
from py_trees.common import Status

from sar_framework.engine.plugin import Param, leaf
from sar_framework.events.emitter import NO_EVENTS, EventEmitter, events_from
from sar_framework.events.event import EventKind

#: The levels, as the ROS logger (and Python's) names its methods.
LEVELS = ("debug", "info", "warning", "error")


@leaf(params=[Param("message", str, description="The line to say."),
              Param("level", str, default="info", enum=LEVELS,
                    description="The logger level: debug, info, warning or error.")])
class Log(py_trees.behaviour.Behaviour):
    """Log ``message`` at ``level`` and record it as a ``note`` event; SUCCESS.

    The line goes to the ROS node's logger when ``setup(node=...)`` gave one, otherwise to
    the py_trees logger; the event (status: the level, upper case) to the emitter
    ``setup(events=...)`` gave, which ``sar-tree run`` shows and records. It becomes the
    feedback message too.

    Args:
        name: The behaviour's name.
        message: The line.
        level: ``debug``, ``info``, ``warning`` or ``error``.
    """

    def __init__(self, name: str, *, message: str, level: str) -> None:
        super().__init__(name=name)
        self.message = message
        self.level = level
        self._node: Any = None
        self._events: EventEmitter = NO_EVENTS

    def setup(self, **kwargs: Any) -> None:
        """Keep the ROS node (for its logger) and the event emitter, when given."""
        self._node = kwargs.get("node")
        self._events = events_from(kwargs)

    def update(self) -> Status:
        """Say the line; SUCCESS."""
        self.feedback_message = self.message
        self._events.emit(EventKind.NOTE, source=self, status=self.level.upper(),
                          message=self.message)
        logger = self._node.get_logger() if self._node is not None else self.logger
        getattr(logger, self.level)(self.message)
        return Status.SUCCESS
