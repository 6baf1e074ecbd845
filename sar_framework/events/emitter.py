"""EventEmitter: the one API through which the runner and the leaves emit events (no ROS).

The runner makes one emitter per mission, with its clock and its sinks (the JSON-lines
file, the ROS topic), and hands it to every behaviour the py_trees_ros way: ``setup(node=...,
events=emitter)``. A leaf keeps it with :func:`events_from` and says what happened::

    def setup(self, **kwargs):
        self.events = events_from(kwargs)
    ...
    self.events.emit(EventKind.NOTE, source=self, message="shelf scanned")
    self.events.emit("shelf_scanned", source=self, shelf="nw", items="12")  # an app's kind

The emitter fills in the stamp, the sequence number and the node's name, uid and kind
(``source``). A tree ticked outside the runner gets :data:`NO_EVENTS`, which drops them.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import Any

from sar_framework.events.event import EventKind, MissionEvent

EventSink = Callable[[MissionEvent], None]
"""Receives every event, in order (a file writer, a topic publisher, a test's list)."""
SETUP_KEY = "events"
"""The ``setup()`` keyword the emitter arrives under."""


class EventEmitter:
    """Stamps, numbers and hands events to its sinks.

    Args:
        sinks: Where events go.
        sim_now: The ROS clock in seconds (wall time since start when None).
        wall_start: ``time.monotonic()`` of the runner's start.
        nodes: ``uid -> (behaviour, kind)`` of the tree, to name an event's ``source``.
    """

    def __init__(self, sinks: Sequence[EventSink] = (), *,
                 sim_now: Callable[[], float] | None = None, wall_start: float | None = None,
                 nodes: Mapping[str, tuple[Any, str]] | None = None) -> None:
        self._sinks = list(sinks)
        self._wall_start = time.monotonic() if wall_start is None else wall_start
        self._sim_now = sim_now or (lambda: time.monotonic() - self._wall_start)
        self._nodes: dict[int, tuple[str, str]] = {}
        self._lock = threading.Lock()
        self._seq = 0
        self.emitted: list[MissionEvent] = []
        if nodes:
            self.know(nodes)

    def know(self, nodes: Mapping[str, tuple[Any, str]]) -> None:
        """Learn the tree's nodes: ``uid -> (behaviour, kind)``."""
        self._nodes.update({id(b): (uid, kind) for uid, (b, kind) in nodes.items()})

    def add_sink(self, sink: EventSink) -> None:
        """Send the events emitted from now on to ``sink`` too."""
        self._sinks.append(sink)

    def emit(self, kind: EventKind | str, *, source: Any = None, status: str = "",
             message: str = "", position: Iterable[float] | None = None,
             **fields: str) -> MissionEvent:
        """Emit one event now; return it as sent.

        Args:
            kind: What happened: an :class:`EventKind`, or an app's kind by name.
            source: The behaviour it concerns (its name, uid and kind are filled in).
            status: A status word (``SUCCESS``, ``FOUND``...).
            message: One line for humans.
            position: ``(x, y)`` or ``(x, y, z)`` metres in the map frame.
            **fields: An app's fields (text); empty values are left out.
        """
        uid, node_kind = self._nodes.get(id(source), ("", "")) if source is not None \
            else ("", "")
        point = None
        if position is not None:
            values = [float(v) for v in position]
            point = (values[0], values[1], values[2] if len(values) > 2 else 0.0)
        with self._lock:
            self._seq += 1
            event = MissionEvent(
                kind=kind, seq=self._seq, sim_s=round(self._sim_now(), 3),
                wall_s=round(time.monotonic() - self._wall_start, 3),
                node_name=str(getattr(source, "name", "")) if source is not None else "",
                node_uid=uid, node_kind=node_kind, status=status, message=message,
                position=point, fields={k: str(v) for k, v in fields.items() if v != ""})
            self.emitted.append(event)
            for sink in self._sinks:
                sink(event)
        return event


class _NoEvents(EventEmitter):
    """An emitter that keeps and sends nothing (a tree ticked outside the runner)."""

    def emit(self, kind: EventKind | str, **_fields: Any) -> MissionEvent:
        """Drop the event; return it unstamped."""
        return MissionEvent(kind=kind)


NO_EVENTS: EventEmitter = _NoEvents()
"""The emitter of a behaviour set up without one."""


def events_from(kwargs: Mapping[str, Any]) -> EventEmitter:
    """The emitter a behaviour's ``setup(**kwargs)`` was given, or :data:`NO_EVENTS`."""
    emitter = kwargs.get(SETUP_KEY)
    return emitter if isinstance(emitter, EventEmitter) else NO_EVENTS
