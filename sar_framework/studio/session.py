"""One studio session: what the page shows (live or replayed), shared by every browser tab.

A :class:`Session` holds the :class:`~sar_framework.studio.timeline.Timeline`, the tree's
diagram (:mod:`.tree_view`) and the map (:mod:`.world_view`). Live, the ROS feed
(:mod:`.ros_feed`) fills it from its own thread and calls :meth:`Session.changed`; the
server's tabs wait on :meth:`Session.wait_change` and send the newest frame. A live
session that knows the mission's tree file draws it from the file (params and ports), and
again after a hot reload swapped it (:meth:`Session.redraw_from_file`). Replayed, it
is filled once from the recording (:func:`replay_session`) and each tab asks for the frame
at the instant its scrubber shows.

No ROS here.
"""

from __future__ import annotations

import asyncio
import contextlib
import threading
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

from sar_framework.studio.timeline import Timeline, timeline_of
from sar_framework.studio.tree_view import matches, status_tree_view, tree_view
from sar_framework.studio.world_view import occupancy_view, world_view

if TYPE_CHECKING:
    from sar_framework.studio.editor import TreeEditor

LIVE = "live"
REPLAY = "replay"
EDIT = "edit"


class Session:
    """What the studio shows, and who to tell when it changes.

    Args:
        mode: :data:`LIVE`, :data:`REPLAY` or :data:`EDIT`.
        tree: The tree view from a tree file, if any (else drawn from the first status).
        world: The map view.
        title: A line for the page's header (the recording or the domain).
    """

    def __init__(self, mode: str, tree: dict[str, Any] | None, world: dict[str, Any],
                 title: str) -> None:
        self.mode = mode
        self.tree = tree
        self.world = world
        self.title = title
        self.timeline = Timeline()
        self.lock = threading.Lock()
        self.version = 0
        #: The editor's file, text and completions (``edit`` mode; live, the mission's file).
        self.edit: dict[str, Any] | None = None
        #: The mission's tree file being edited (live, when known; :mod:`.editor`).
        self.editor: TreeEditor | None = None
        #: Live, without a tree file given: told the file the mission's runner says it ticks.
        self.learn_tree: Callable[[str], None] | None = None
        #: Draws the mission's tree file (None when it does not validate); live, when known.
        self.draw_file: Callable[[], dict[str, Any] | None] | None = None
        self._file_tree = tree if tree is not None and tree.get("source") == "file" else None
        self._listeners: dict[int, Callable[[], None]] = {}

    # -- filled by the feed (any thread) -------------------------------------------------------
    def changed(self) -> None:
        """Say that the timeline, tree or map changed (call after adding, lock released)."""
        self.version += 1
        for listener in list(self._listeners.values()):
            listener()

    def adopt_status_tree(self, document: dict[str, Any]) -> bool:
        """Draw the tree from a status document when the known diagram does not fit it.

        Returns:
            Whether the diagram changed (a first status, or a tree of other nodes).
        """
        if self.tree is not None and matches(self.tree, document["nodes"]):
            return False
        if self._file_tree is not None and matches(self._file_tree, document["nodes"]):
            self.tree = self._file_tree
            return True
        self.tree = status_tree_view(document.get("tree", "tree"), document["nodes"])
        return True

    def redraw_from_file(self) -> None:
        """Draw the tree again from its file (after a hot reload swapped it in; any thread).

        The new drawing is shown as soon as the statuses list its nodes (at once when they
        already do); until then the diagram stays the one that fits them.
        """
        if self.draw_file is None:
            return
        view = self.draw_file()
        if view is None:
            return
        with self.lock:
            self._file_tree = view
            statuses = self.timeline.statuses
            if not statuses or matches(view, statuses[-1]["nodes"]):
                self.tree = view
        self.changed()

    # -- read by the server ------------------------------------------------------------------
    def listen(self, loop: asyncio.AbstractEventLoop) -> asyncio.Event:
        """An event set (in ``loop``) whenever the session changes."""
        event = asyncio.Event()

        def wake() -> None:
            with contextlib.suppress(RuntimeError):  # the loop closed: the server stopped
                loop.call_soon_threadsafe(event.set)

        self._listeners[id(event)] = wake
        return event

    def forget(self, event: asyncio.Event) -> None:
        """Stop telling ``event`` (a closed tab)."""
        self._listeners.pop(id(event), None)

    def hello(self) -> dict[str, Any]:
        """Everything a tab draws once: mode, tree, map and the timeline's span and marks.

        Replayed, the timeline also lists every event (:meth:`Timeline.event_rows`), for
        the page's event list.
        """
        with self.lock:
            timeline = {"start": self.timeline.start_s, "end": self.timeline.end_s,
                        "marks": self.timeline.marks()}
            if self.mode == REPLAY:
                timeline["events"] = self.timeline.event_rows()
            return {"type": "hello", "mode": self.mode, "title": self.title,
                    "tree": self.tree, "world": self.world, "version": self.version,
                    "timeline": timeline, "edit": self.edit}

    def frame(self, t: float | None = None) -> dict[str, Any]:
        """The frame at ``t`` (the newest when None)."""
        with self.lock:
            frame = self.timeline.frame(t)
            frame.update(type="frame", version=self.version, end=self.timeline.end_s)
            return frame

    def node_detail(self, uid: str, t: float | None = None) -> dict[str, Any]:
        """A node's facts, status history and last reason at ``t``."""
        with self.lock:
            facts = (self.tree or {}).get("nodes", {}).get(uid)
            detail = self.timeline.node_detail(uid, t)
        return {"type": "node", "facts": facts, **detail}


def replay_session(path: Path, sources_dir: Path) -> Session:
    """A session showing a recording (``sar-tree run --record``).

    Args:
        path: The ``.mcap`` file.
        sources_dir: Where the recorded tree files are written to be validated again.

    Raises:
        RecordingError: Not a recording of ours, or no tree status in it.
    """
    from sar_framework.recording.readback import RecordingError, read_recording
    from sar_framework.recording.recorder import ATTACHMENT_PARAMS
    from sar_framework.recording.replay import recorded_tree

    recording = read_recording(path)
    if not recording.statuses:
        raise RecordingError(f"{path}: no tree status in the recording "
                             "(was it recorded with sar-tree run --record?)")
    tree = None
    try:
        recorded = recorded_tree(recording, sources_dir)
    except RecordingError:
        recorded = None
    if recorded is not None and recorded.spec is not None:
        tree = tree_view(recorded.spec)
        original = recording.metadata.get("tree")
        for facts in tree["nodes"].values() if original and recorded.file else ():
            # where the recorded tree was, not the copy it was validated from
            facts["location"] = facts["location"].replace(str(recorded.file), original, 1)
    params = None
    if ATTACHMENT_PARAMS in recording.attachments:
        params = sources_dir / ATTACHMENT_PARAMS
        params.parent.mkdir(parents=True, exist_ok=True)
        params.write_bytes(recording.attachments[ATTACHMENT_PARAMS])
    grid = occupancy_view(recording.map) if recording.map is not None else None
    apps = recorded.apps if recorded is not None else None  # the run's, plugins: ones too
    session = Session(REPLAY, tree, world_view(params, grid, apps), str(path))
    session.timeline = timeline_of(recording, apps)
    session.adopt_status_tree(recording.statuses[0])
    return session
