"""One mission event: its kinds, its fields and its JSON encoding (no ROS).

The ROS twin is ``sar_interfaces/msg/MissionEvent`` (the same fields; the core's kind names
are its ``KIND_*`` constants); :mod:`sar_framework.runner.event_topic` converts between them.
An app's events carry kinds of the app's own and its fields as key/value pairs
(``fields``, a ``diagnostic_msgs/KeyValue[]`` on the topic), so a new app needs no new
message. A JSON line holds every field, for example::

    {"seq": 7, "kind": "goal_reached", "sim_s": 21.4, "wall_s": 2.1, "node_name": "GoHome",
     "node_uid": "0.5", "node_kind": "NavigateToPose", "status": "SUCCEEDED",
     "message": "navigate_to_pose succeeded", "position": [0.0, 0.0, 0.0], "fields": {}}
"""

from __future__ import annotations

import enum
import json
import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, field, fields, replace
from typing import Any

EVENT_TOPIC_NAME = "sar_mission/events"
"""The runner's event topic, relative: ``/robot1/sar_mission/events`` for a runner in
``/robot1`` (:mod:`sar_framework.runner.event_topic`)."""
EVENT_TOPIC = "/" + EVENT_TOPIC_NAME
"""The same topic in the root namespace: a single robot's runner publishes it there."""
EVENT_TYPE = "sar_interfaces/msg/MissionEvent"
"""Its message type."""


def in_namespace(relative: str, namespace: str = "") -> str:
    """The full name of a relative topic in ``namespace``.

    Args:
        relative: A relative name (``sar_mission/events``).
        namespace: ``robot1``, ``/robot1`` or ``""``/``"/"`` for the root namespace.

    Returns:
        ``/robot1/sar_mission/events`` (``/sar_mission/events`` in the root).
    """
    namespace = namespace.strip("/")
    return f"/{namespace}/{relative}" if namespace else f"/{relative}"


class EventKind(str, enum.Enum):
    """What an event says happened: the core's kinds (the ``KIND_*`` constants of the message).

    An app's kinds are its own (a ``str`` enum of lower-case names, or plain names).
    """

    STARTED = "started"
    STATUS = "status"
    FAILURE = "failure"
    TIMEOUT = "timeout"
    CANCEL = "cancel"
    RETRY = "retry"
    SKIP = "skip"
    NAVIGATION = "navigation"
    GOAL_REACHED = "goal_reached"
    GOAL_FAILED = "goal_failed"
    NOTE = "note"
    COMPLETION = "completion"
    VERDICT = "verdict"
    TREE_SWAPPED = "tree_swapped"
    RELOAD_REFUSED = "reload_refused"


#: An app's own event kind: a lower-case name (``shelf_scanned``).
APP_KIND = re.compile(r"[a-z][a-z0-9_]*")


def kind_name(kind: EventKind | str) -> str:
    """The name of a kind, the core's or an app's (``goal_reached``; an app's enum's value)."""
    return str(getattr(kind, "value", kind))


def event_kind(name: str) -> EventKind | str:
    """The core's :class:`EventKind` called ``name``, else ``name`` as an app's kind.

    Raises:
        EventFormatError: ``name`` is not a kind name.
    """
    try:
        return EventKind(name)
    except ValueError:
        if isinstance(name, str) and APP_KIND.fullmatch(name):
            return name
        raise EventFormatError(f"unknown kind {name!r}") from None


#: The reasons the runner records for a failing or halted part of the tree.
REASON_KINDS = frozenset({EventKind.FAILURE, EventKind.TIMEOUT, EventKind.CANCEL,
                          EventKind.RETRY, EventKind.SKIP})
#: The reasons that are causes of a failure (the others are what the tree did about one).
CAUSE_KINDS = frozenset({EventKind.FAILURE, EventKind.TIMEOUT})


class EventFormatError(ValueError):
    """A JSON line or document that is not a mission event."""


@dataclass(frozen=True)
class MissionEvent:
    """One event of the stream.

    Attributes:
        kind: What happened: an :class:`EventKind`, or an app's kind by name.
        seq: 1, 2, 3... in emission order (0 before the emitter numbered it).
        sim_s: The runner's ROS clock in seconds (simulated time with ``use_sim_time``).
        wall_s: Wall seconds since the runner started.
        node_name: The tree node it concerns ("" for the mission as a whole).
        node_uid: That node's uid.
        node_kind: That node's kind.
        status: ``SUCCESS``, ``FAILURE``, ``RUNNING``, ``FOUND``, ``NONE``... or "".
        message: One line for humans (never parsed).
        position: ``(x, y, z)`` metres in the map frame, or None.
        fields: An app's fields, key -> value (text), as ``diagnostic_msgs/KeyValue``.
    """

    kind: EventKind | str
    seq: int = 0
    sim_s: float = 0.0
    wall_s: float = 0.0
    node_name: str = ""
    node_uid: str = ""
    node_kind: str = ""
    status: str = ""
    message: str = ""
    position: tuple[float, float, float] | None = None
    fields: Mapping[str, str] = field(default_factory=dict)

    def value(self, key: str) -> str:
        """The app field ``key``, or "" when the event has none."""
        return self.fields.get(key, "")

    def numbered(self, seq: int) -> MissionEvent:
        """This event with sequence number ``seq``."""
        return replace(self, seq=seq)

    def to_dict(self) -> dict[str, Any]:
        """The JSON-ready mapping (``kind`` as its name, ``position`` a list or None)."""
        document = {f.name: getattr(self, f.name) for f in fields(self)}
        document["kind"] = kind_name(self.kind)
        document["position"] = list(self.position) if self.position is not None else None
        document["fields"] = dict(self.fields)
        return document

    def to_json(self) -> str:
        """One JSON line (no newline)."""
        return json.dumps(self.to_dict(), separators=(",", ":"), allow_nan=False)


_TEXT_FIELDS = ("node_name", "node_uid", "node_kind", "status", "message")


def _number(document: dict[str, Any], key: str) -> float:
    value = document.get(key, 0.0)
    if isinstance(value, bool) or not isinstance(value, (int, float)) \
            or not math.isfinite(value):
        raise EventFormatError(f"{key} must be a finite number, got {value!r}")
    return float(value)


def event_from_dict(document: Any) -> MissionEvent:
    """Read an event back from :meth:`MissionEvent.to_dict`'s mapping.

    Args:
        document: The decoded JSON value.

    Returns:
        The event.

    Raises:
        EventFormatError: Not a mapping, an unknown kind, or a field of the wrong type.
    """
    if not isinstance(document, dict):
        raise EventFormatError(f"an event is a JSON object, got {type(document).__name__}")
    unknown = set(document) - {f.name for f in fields(MissionEvent)}
    if unknown:
        raise EventFormatError(f"unknown field(s): {', '.join(sorted(unknown))}")
    kind = event_kind(document.get("kind"))
    seq = document.get("seq", 0)
    if isinstance(seq, bool) or not isinstance(seq, int) or seq < 0:
        raise EventFormatError(f"seq must be a natural number, got {seq!r}")
    texts = {key: document.get(key, "") for key in _TEXT_FIELDS}
    for key, value in texts.items():
        if not isinstance(value, str):
            raise EventFormatError(f"{key} must be a string, got {value!r}")
    position = document.get("position")
    if position is not None:
        if not isinstance(position, list) or len(position) != 3:
            raise EventFormatError(f"position must be [x, y, z] or null, got {position!r}")
        position = tuple(_number({"position": v}, "position") for v in position)
    app_fields = document.get("fields", {})
    if not isinstance(app_fields, dict) or not all(
            isinstance(k, str) and isinstance(v, str) for k, v in app_fields.items()):
        raise EventFormatError(f"fields must map names to strings, got {app_fields!r}")
    return MissionEvent(kind=kind, seq=seq, sim_s=_number(document, "sim_s"),
                        wall_s=_number(document, "wall_s"), position=position,
                        fields=app_fields, **texts)


def event_from_json(line: str) -> MissionEvent:
    """Parse one JSON line.

    Raises:
        EventFormatError: Not JSON, or not an event.
    """
    try:
        document = json.loads(line)
    except ValueError as err:
        raise EventFormatError(f"not JSON: {err}") from None
    return event_from_dict(document)
