"""A mission as the studio shows it: every tick, event and pose, and the frame at any instant.

:class:`Timeline` is filled in time order (:meth:`Timeline.add_status`,
:meth:`Timeline.add_event`, :meth:`Timeline.add_pose`): live from the ROS feed as messages
arrive, or all at once from a recording (:func:`timeline_of`). :meth:`Timeline.frame`
answers "what did the mission look like at ``t``" by bisection over those lists, so a
scrub through a recording of many minutes costs the same as one at its start: the tick's
node statuses, blackboard and entries, the robot's pose and path so far, what the
apps add (the places reached, what was found: :attr:`~sar_framework.app.App.frame`) and the
latest reasons. Times are the runner's ROS clock
(``sim_s``), the clock the status, the events and the poses share.

No ROS here: the documents are :func:`~sar_framework.runner.tree_status.decode_status`'s
and the events :class:`~sar_framework.events.event.MissionEvent`.
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from sar_framework.app.discovery import installed_apps
from sar_framework.events.event import REASON_KINDS, EventKind, MissionEvent, kind_name
from sar_framework.runner.entry_values import apply_entries

if TYPE_CHECKING:
    from sar_framework.app import App
    from sar_framework.recording.readback import Recording

#: Reasons a frame carries (the latest).
REASONS_SHOWN = 40
#: The path keeps a pose only this far (metres) from the previous one kept.
PATH_STEP_M = 0.05
#: The window (seconds of the clock the statuses arrive by) ticks per second are counted on.
RATE_WINDOW_S = 2.0
#: Events (by kind name) that mark the replay timeline, and the mark's kind (the apps add
#: theirs: :attr:`~sar_framework.app.App.marks`).
MARKS = {EventKind.FAILURE.value: "failure", EventKind.TIMEOUT.value: "failure",
         EventKind.GOAL_REACHED.value: "reached", EventKind.GOAL_FAILED.value: "failure",
         EventKind.COMPLETION.value: "end", EventKind.TREE_SWAPPED.value: "swap",
         EventKind.RELOAD_REFUSED.value: "refused"}
#: Events the reasons feed lists: the reasons, and hot reload's swaps and refusals
#: (docs/how-to/hot-reload.md).
FEED_KINDS = REASON_KINDS | {EventKind.TREE_SWAPPED, EventKind.RELOAD_REFUSED}


@dataclass
class Timeline:
    """What a mission did, in time order, with the frame at any instant.

    Attributes:
        statuses: Status documents, by tick; each has ``sim_s`` and ``arrival_s`` (the
            clock ticks per second are measured by: wall seconds live, ``wall_s`` replayed).
        events: The mission's events in order.
        poses: ``(sim_s, x, y, yaw)`` of the robot in the map frame.
        apps: The apps whose marks, frame keys and status words it adds (the installed).
    """

    statuses: list[dict[str, Any]] = field(default_factory=list)
    events: list[MissionEvent] = field(default_factory=list)
    poses: list[tuple[float, float, float, float]] = field(default_factory=list)
    _status_times: list[float] = field(default_factory=list)
    _arrivals: list[float] = field(default_factory=list)
    _entries: list[dict[str, dict[str, str]]] = field(default_factory=list)
    _event_times: list[float] = field(default_factory=list)
    _reasons: list[int] = field(default_factory=list)
    _pose_times: list[float] = field(default_factory=list)
    _path: list[tuple[float, float]] = field(default_factory=list)
    _path_times: list[float] = field(default_factory=list)
    _history: dict[str, list[tuple[float, str]]] = field(default_factory=dict)
    apps: Sequence[App] = field(default_factory=installed_apps)

    # -- filling ----------------------------------------------------------------------------
    def add_status(self, document: dict[str, Any], arrival_s: float) -> None:
        """Add one tick's status document (``decode_status``'s form).

        Args:
            document: The document.
            arrival_s: When it arrived (seconds, any clock that only moves forward).
        """
        sim_s = float(document.get("sim_s", 0.0))
        if self._status_times and sim_s < self._status_times[-1]:
            sim_s = self._status_times[-1]  # the clock never runs back on the timeline
        previous = self._entries[-1] if self._entries else {}
        entries = apply_entries(previous, document["entries"],
                                full=bool(document.get("entries_full"))) \
            if "entries" in document else previous
        before = {n["uid"]: n["status"] for n in self.statuses[-1]["nodes"]} \
            if self.statuses else {}
        for node in document["nodes"]:
            if before.get(node["uid"]) != node["status"]:
                self._history.setdefault(node["uid"], []).append((sim_s, node["status"]))
        self.statuses.append(document)
        self._status_times.append(sim_s)
        self._arrivals.append(arrival_s)
        self._entries.append(entries)

    def add_event(self, event: MissionEvent) -> None:
        """Add one mission event."""
        sim_s = max(event.sim_s, self._event_times[-1]) if self._event_times else event.sim_s
        if event.kind in FEED_KINDS:
            self._reasons.append(len(self.events))
        self.events.append(event)
        self._event_times.append(sim_s)

    def add_pose(self, sim_s: float, x: float, y: float, yaw: float) -> None:
        """Add one robot pose (map frame, metres and radians)."""
        if self._pose_times and sim_s < self._pose_times[-1]:
            sim_s = self._pose_times[-1]
        self.poses.append((sim_s, x, y, yaw))
        self._pose_times.append(sim_s)
        if not self._path or math.hypot(x - self._path[-1][0],
                                        y - self._path[-1][1]) >= PATH_STEP_M:
            self._path.append((round(x, 3), round(y, 3)))
            self._path_times.append(sim_s)

    # -- reading ----------------------------------------------------------------------------
    @property
    def start_s(self) -> float:
        """The first tick's instant (else the first event's; 0 for an empty timeline).

        Events from before the first tick (``started``, stamped before the clock ran) are
        shown from the start.
        """
        times = self._status_times or self._event_times
        return times[0] if times else 0.0

    @property
    def end_s(self) -> float:
        """The last instant anything happened."""
        lasts = [times[-1] for times in (self._status_times, self._event_times, self._pose_times)
                 if times]
        return max(lasts) if lasts else 0.0

    def marks(self) -> list[dict[str, Any]]:
        """The timeline's marks: failures, arrivals, finds, reloads and the end."""
        marks = self._marks()
        return [{"t": self._event_times[i], "kind": marks[kind_name(e.kind)], "seq": e.seq,
                 "label": _event_label(e)}
                for i, e in enumerate(self.events) if kind_name(e.kind) in marks]

    def _marks(self) -> dict[str, str]:
        return {**{k: v for app in self.apps for k, v in app.marks.items()}, **MARKS}

    def event_rows(self) -> list[dict[str, Any]]:
        """Every event in order, for the replay's event list, each with the instant it links to.

        Returns:
            ``[{"i", "t", "sim_s", "seq", "kind", "node", "uid", "status", "fields",
            "mark", "message"}, ...]`` (``fields``: an app's values, in order; ``mark``: the
            timeline mark of its kind, or ""): ``t`` is the event's
            instant on the timeline (never before :attr:`start_s`: an event stamped before
            the first tick, such as ``started``, links to the start), ``sim_s`` the event's
            own stamp.
        """
        start, marks = self.start_s, self._marks()
        return [{"i": i, "t": max(t, start), "sim_s": e.sim_s, "seq": e.seq,
                 "kind": kind_name(e.kind), "node": e.node_name, "uid": e.node_uid,
                 "status": e.status, "fields": list(e.fields.values()),
                 "mark": marks.get(kind_name(e.kind), ""),
                 "message": e.message}
                for i, (e, t) in enumerate(zip(self.events, self._event_times, strict=True))]

    def frame(self, t: float | None = None) -> dict[str, Any]:
        """The mission at ``t`` (the latest when None), as the page draws it.

        Returns:
            ``{"t", "tick", "status", "complete", "app_status", "nodes": {uid: [status,
            message, visited]}, "blackboard", "entries", "tps", "robot": [x, y, yaw] | None,
            "path": [[x, y], ...], "reached", "found", "reasons"}``: ``app_status`` the
            apps' words about the tick's status ("" for none), ``reached`` the ids of the
            places reached and ``found`` what was found (``[{"id", "position"}]``), from the
            apps (:attr:`~sar_framework.app.App.frame`).
        """
        t = self.end_s if t is None else t
        i = bisect.bisect_right(self._status_times, t) - 1
        status = self.statuses[i] if i >= 0 else {}
        j = bisect.bisect_right(self._event_times, t)
        k = bisect.bisect_right(self._pose_times, t) - 1
        p = bisect.bisect_right(self._path_times, t)
        reasons = self._reasons[:bisect.bisect_left(self._reasons, j)][-REASONS_SHOWN:]
        return {
            "t": t, "tick": status.get("tick", 0), "status": status.get("status", "INVALID"),
            "complete": bool(status.get("complete")),
            "app_status": "  ".join(app.status_text(status) for app in self.apps
                                    if app.status_text and app.status_text(status)),
            "nodes": {n["uid"]: [n["status"], n["message"], n["visited"]]
                      for n in status.get("nodes", [])},
            "blackboard": status.get("blackboard", {}),
            "entries": self._entries[i] if i >= 0 else {},
            "tps": self._rate(i),
            "robot": list(self.poses[k][1:]) if k >= 0 else None,
            "path": self._path[:p],
            "reached": [], "found": [],
            **self._app_frame(self.events[:j]),
            "reasons": [self._reason(n) for n in reversed(reasons)],
        }

    def node_detail(self, uid: str, t: float | None = None) -> dict[str, Any]:
        """A node's status history up to ``t`` and its last reason, for the node panel."""
        t = self.end_s if t is None else t
        history = self._history.get(uid, [])
        history = history[:bisect.bisect_right([h[0] for h in history], t)]
        j = bisect.bisect_right(self._event_times, t)
        last = next((self._reason(n) for n in reversed(self._reasons)
                     if n < j and self.events[n].node_uid == uid), None)
        return {"uid": uid, "history": [[s, status] for s, status in history[-50:]],
                "last_reason": last}

    def _app_frame(self, events: list[MissionEvent]) -> dict[str, Any]:
        added: dict[str, Any] = {}
        for app in self.apps:
            if app.frame is not None:
                for key, value in app.frame(events).items():
                    added[key] = [*added.get(key, []), *value]
        return added

    def _rate(self, i: int) -> float:
        if i < 1:
            return 0.0
        now = self._arrivals[i]
        first = bisect.bisect_left(self._arrivals, now - RATE_WINDOW_S, 0, i + 1)
        span = now - self._arrivals[first]
        return round((i - first) / span, 1) if span > 0 else 0.0

    def _reason(self, n: int) -> dict[str, Any]:
        event = self.events[n]
        return {"t": self._event_times[n], "seq": event.seq, "kind": kind_name(event.kind),
                "node": event.node_name, "uid": event.node_uid, "message": event.message}


def _event_label(event: MissionEvent) -> str:
    subject = next((v for v in event.fields.values() if v), "") or event.node_name
    return f"{kind_name(event.kind)} {subject}".strip()


def timeline_of(recording: Recording, apps: Sequence[App] | None = None) -> Timeline:
    """The timeline of a decoded recording: its statuses, events and poses in time order.

    Args:
        recording: :func:`~sar_framework.recording.readback.read_recording`'s result.
        apps: The apps whose marks, frame keys and status words it adds (the installed
            ones when None).
    """
    timeline = Timeline() if apps is None else Timeline(apps=apps)
    for document in recording.statuses:
        timeline.add_status(document, float(document.get("wall_s", 0.0)))
    for event in sorted(recording.events, key=lambda e: (e.sim_s, e.seq)):
        timeline.add_event(event)
    for sim_s, x, y, yaw in sorted(recording.poses, key=lambda p: p[0]):
        timeline.add_pose(sim_s, x, y, yaw)
    return timeline
