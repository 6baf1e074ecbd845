"""The runner's status file, the tree's snapshot kept current; and the status events.

What *happened* goes out as events (:mod:`sar_framework.events`): :class:`StatusFileWriter`
emits a ``status`` event when a leaf starts (RUNNING) and when it ends SUCCESS or FAILURE
(a leaf repeating the same verdict and message on consecutive ticks, a reactive root
re-checking a condition while the tree idles, once), and collects the reasons
(:mod:`.reasons`) the runner emits. The file holds what *is* (docs/reference/mission-contracts.md,
"Runner status file")::

    {"tree": "trees/search_and_rescue.yaml", "status": "SUCCESS", "ticks": 412,
     "wall_first_tick_s": 0.8, "sim_start_s": 0.0, "sim_end_s": 151.2, "wall_duration_s": 9.1,
     "nodes": {"0": "SUCCESS", "0.0": "FAILURE", ...}, "running": [], "complete": true}

Definitions used here:

- ``sim_*`` are readings of the runner node's ROS clock in seconds (``/clock`` time with
  ``use_sim_time``); ``wall_*`` are wall-clock seconds since the runner started.
- ``nodes`` maps each ``NodeSpec.uid`` to its last non-INVALID status, the ones it had
  during a tick included (a leaf started and halted within one tick keeps RUNNING, as
  its events say); ``running`` lists the uids RUNNING after the last tick.
- The reasons (:attr:`StatusFileWriter.failures`) are the leaf FAILUREs that are failures
  rather than decisions: the leaf had been RUNNING before it failed (conditions never run,
  so a condition saying "no" is not listed), or its FAILURE came on the tick the root
  itself failed; and every timeout, cancel, retry and skip, each with ``what``.
- A runner that stops before its first tick writes ``error``: ``{"step", "message"}``.
- ``complete`` (an addition to the contract's keys) says the mission is over
  (:mod:`sar_framework.mission.completion`). With ``completion="end"`` that is the first
  tick the root FAILS, or SUCCEEDS while the one_shot on the tree's final path
  (``end_uid``) has latched (no such one_shot: the root's first SUCCESS). With
  ``completion="once"`` it is the first tick the root is SUCCESS or FAILURE. With
  ``completion="rest"`` it is once the tree is *at rest*: the root had the same terminal
  status on two consecutive ticks and the second tick changed nothing (every status the
  same, no new leaf verdict). With
  ``completion="forever"`` the mission is never complete. Once complete, always complete:
  the mission's figures (``status``, ``ticks``, ``sim_end_s``, ``wall_duration_s``, node
  statuses) are frozen at that tick, so a runner kept alive afterwards does not count on.

The file is written atomically (temporary file + rename) whenever something changed.
"""

from __future__ import annotations

import json
import os
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import py_trees
from py_trees.common import Status

from sar_framework.engine.spec import Category, TreeSpec
from sar_framework.events.emitter import NO_EVENTS, EventEmitter
from sar_framework.events.event import EventKind
from sar_framework.runner.entry_values import EntryTracker
from sar_framework.runner.reasons import EXPLAINING_DECORATORS, ReasonLog, recovers

_TERMINAL = (Status.SUCCESS, Status.FAILURE)
#: How the end of a mission is recognised (see the module docstring).
RECORDED_COMPLETIONS = ("end", "once", "rest", "forever")


def write_json_atomically(path: str | Path, document: dict[str, Any]) -> None:
    """Write ``document`` as JSON to ``path`` via a temporary file and a rename.

    Args:
        path: The target file; its folder is created if missing.
        document: A JSON-serialisable mapping.
    """
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, temp = tempfile.mkstemp(prefix=f".{target.name}.", dir=target.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as handle:
            json.dump(document, handle, indent=1)
            handle.write("\n")
        os.replace(temp, target)
    except BaseException:
        Path(temp).unlink(missing_ok=True)
        raise


def startup_failure_document(tree: str, step: str, message: str,
                             wall_duration_s: float) -> dict[str, Any]:
    """Return a status document for a runner that stopped before its first tick.

    Args:
        tree: The tree file as given.
        step: What failed (``parameters``, ``tree``, ``nav2``, ``setup``).
        message: Why.
        wall_duration_s: Seconds since the runner started.
    """
    return {
        "tree": tree, "status": Status.INVALID.name, "ticks": 0,
        "wall_first_tick_s": None, "sim_start_s": None, "sim_end_s": None,
        "wall_duration_s": round(wall_duration_s, 3),
        "nodes": {}, "running": [], "complete": False,
        "error": {"step": step, "message": message},
    }


class StatusFileWriter(py_trees.visitors.VisitorBase):
    """Watches a ticking tree and keeps the status document (and file) current.

    Add it to ``tree.visitors`` (it sees every behaviour ticked) and call
    :meth:`after_tick` from a post-tick handler.

    Args:
        tree_file: The tree file as given (goes into the document).
        spec: The validated tree (uids, leaf kinds).
        behaviours: ``NodeSpec.uid -> behaviour`` from ``load_tree``.
        sim_now: Returns the ROS clock in seconds.
        path: The status file; None keeps the document in memory only.
        wall_start: ``time.monotonic()`` when the runner started.
        completion: ``"end"``, ``"once"``, ``"rest"`` or ``"forever"`` (see the module
            docstring).
        end_uid: The uid of the one_shot on the tree's final path (``completion="end"``).
        emitter: Where each leaf's start (RUNNING) and verdict go as ``status`` events.
        entries: The tree's blackboard entries; with any, the document lists their last
            values under ``entries`` (as :meth:`.EntryTracker.final` gives them).

    Raises:
        ValueError: An unknown ``completion``.
    """

    def __init__(self, tree_file: str, spec: TreeSpec,
                 behaviours: dict[str, py_trees.behaviour.Behaviour],
                 sim_now: Callable[[], float], *, path: str | Path | None = None,
                 wall_start: float | None = None, completion: str = "rest",
                 emitter: EventEmitter = NO_EVENTS, end_uid: str | None = None,
                 entries: EntryTracker | None = None) -> None:
        super().__init__(full=False)
        self._entries = entries
        if completion not in RECORDED_COMPLETIONS:
            raise ValueError(f"completion must be one of {RECORDED_COMPLETIONS}, "
                             f"got {completion!r}")
        self._completion = completion
        self._end_uid = end_uid
        self._frozen: dict[str, Any] | None = None
        self._emitter = emitter
        self._tree_file = tree_file
        self._path = Path(path) if path else None
        self._sim_now = sim_now
        self._wall_start = time.monotonic() if wall_start is None else wall_start
        self._know(spec, behaviours)
        self.new_reasons: list[dict[str, Any]] = []
        self.nodes: dict[str, str] = {}
        self.events: list[dict[str, Any]] = []
        self.failures: list[dict[str, Any]] = []
        self.ticks = 0
        self.status = Status.INVALID
        self.wall_first_tick_s: float | None = None
        self.sim_start_s: float | None = None
        self._last_event: dict[str, tuple[int, str, str]] = {}
        self._running: set[str] = set()
        self.running: list[str] = []
        self._tick_failures: list[dict[str, Any]] = []
        self._changed = False
        self._snapshot: tuple[Status, ...] = ()
        self.complete = False
        #: When each start-up step was done (wall seconds), listed as ``startup``.
        self.startup: dict[str, float] = {}

    def retarget(self, spec: TreeSpec, behaviours: dict[str, py_trees.behaviour.Behaviour],
                 end_uid: str | None, entries: EntryTracker | None = None) -> None:
        """Follow a swapped tree (between ticks); a kept behaviour keeps what was noted of it.

        Args:
            spec: The new tree.
            behaviours: Its ``uid -> behaviour``.
            end_uid: The uid of the one_shot on its final path, if any.
            entries: The new tree's blackboard entries.
        """
        if entries is not None:
            self._entries = entries
        renamed = {self._uid_of[id(b)]: uid for uid, b in behaviours.items()
                   if id(b) in self._uid_of}
        self._know(spec, behaviours)
        self._end_uid = end_uid
        self.nodes = {renamed[u]: s for u, s in self.nodes.items() if u in renamed}
        self._last_event = {renamed[u]: e for u, e in self._last_event.items() if u in renamed}
        self._running = {renamed[u] for u in self._running if u in renamed}
        self.running = sorted(renamed[u] for u in self.running if u in renamed)
        self._snapshot = ()
        self._changed = True

    def _know(self, spec: TreeSpec, behaviours: dict[str, py_trees.behaviour.Behaviour]) -> None:
        """Learn the tree's nodes and behaviours (what each uid is)."""
        self._behaviours = behaviours
        self._uid_of = {id(b): uid for uid, b in behaviours.items()}
        self._spec_of = {node.uid: node for node in spec.nodes()}
        self._leaves = {node.uid for node in spec.nodes() if node.category == Category.LEAF}
        self._explaining = {node.uid for node in spec.nodes()
                            if node.kind in EXPLAINING_DECORATORS
                            or recovers(behaviours.get(node.uid))}
        self._reasons = ReasonLog({n.uid: n.kind for n in spec.nodes()}, behaviours)
        self.root_uid = spec.root.uid

    # -- visitor: every behaviour ticked this tick --------------------------------------------
    def run(self, behaviour: py_trees.behaviour.Behaviour) -> None:
        """Record a leaf's verdict (py_trees calls this for each ticked behaviour)."""
        uid = self._uid_of.get(id(behaviour))
        if uid is not None and not self.complete:
            self._note(uid, behaviour.status)
        if uid in self._explaining:
            self._reasons.decorator_ticked(uid, self._running, self._stamp())
        if uid is None or uid not in self._leaves:
            return
        status = behaviour.status
        if status == Status.RUNNING:
            if uid not in self._running:
                self._emitter.emit(EventKind.STATUS, source=behaviour, status=status.name,
                                  message=str(behaviour.feedback_message or ""))
            self._running.add(uid)
            return
        if status not in _TERMINAL:
            return
        was_running = uid in self._running
        self._running.discard(uid)
        if status == Status.SUCCESS and was_running:
            self._reasons.leaf_succeeded(uid)
        message = str(behaviour.feedback_message or "")
        key = (status.name, message)
        previous = self._last_event.get(uid)
        self._last_event[uid] = (self.ticks, *key)
        if previous is not None and previous[0] == self.ticks - 1 and previous[1:] == key:
            return  # the same verdict again on the next tick: the tree is idling
        if self.sim_start_s is None:
            self._start()
        event = {
            **self._stamp(), "uid": uid, "name": behaviour.name,
            "kind": self._spec_of[uid].kind, "status": status.name, "message": message,
        }
        self.events.append(event)
        self._emitter.emit(EventKind.STATUS, source=behaviour, status=status.name,
                          message=message)
        self._changed = True
        if status == Status.FAILURE:
            if was_running:
                self._reasons.leaf_failed(uid, message, self._stamp())
            else:
                self._reasons.leaf_said_no(uid, message)
                self._tick_failures.append({"what": "failure", "uid": uid,
                                            "name": behaviour.name,
                                            "kind": self._spec_of[uid].kind,
                                            "message": message, **self._stamp()})

    def _note(self, uid: str, status: Status) -> None:
        """Keep ``status`` as the node's last one in ``nodes``, unless it is INVALID."""
        if status != Status.INVALID and self.nodes.get(uid) != status.name:
            self.nodes[uid] = status.name
            self._changed = True

    def _stamp(self) -> dict[str, float]:
        return {"sim_s": round(self._sim_now(), 3),
                "wall_s": round(time.monotonic() - self._wall_start, 3)}

    # -- after each tick -----------------------------------------------------------------------
    def after_tick(self, tree: py_trees.trees.BehaviourTree) -> bool:
        """Update node statuses after a tick; write the file when anything changed.

        Args:
            tree: The tree just ticked.

        Returns:
            Whether any node's status or the events changed on this tick.
        """
        if self.sim_start_s is None:
            self._start()
        if self.complete:
            return False  # the mission's figures stay those of its completion
        self.ticks += 1
        for uid, behaviour in self._behaviours.items():
            self._note(uid, behaviour.status)
        halted = sorted(u for u in self._running if self._behaviours[u].status == Status.INVALID)
        self._reasons.leaves_halted(halted, self._stamp())
        self._running = {u for u in self._running
                         if self._behaviours[u].status == Status.RUNNING}
        # What runs now (a halted leaf keeps RUNNING in `nodes`, which is for colouring).
        running = sorted(u for u, b in self._behaviours.items() if b.status == Status.RUNNING)
        if running != self.running:
            self.running = running
            self._changed = True
        snapshot = tuple(b.status for b in self._behaviours.values())
        root_status = tree.root.status
        if self._completion == "once":
            complete = root_status in _TERMINAL
        elif self._completion == "end":
            complete = root_status == Status.FAILURE or (
                root_status == Status.SUCCESS and (
                    self._end_uid is None
                    or self._behaviours[self._end_uid].status in _TERMINAL))
        elif self._completion == "forever":
            complete = False
        else:
            complete = (root_status in _TERMINAL and root_status == self.status
                        and snapshot == self._snapshot and not self._changed)
        if complete != self.complete:
            self.complete = complete
            self._changed = True
        self._snapshot = snapshot
        self.status = root_status
        reasons = self._reasons.take()
        if self.status == Status.FAILURE:
            reasons += self._tick_failures  # each failing execution once
        self._tick_failures = []
        if reasons:
            self.failures.extend(reasons)
            self.new_reasons.extend(reasons)
            self._changed = True
        changed, self._changed = self._changed, False
        if self.complete:
            self._frozen = None
            self._frozen = self.document()
        if changed:
            self.write()
        return changed

    def _start(self) -> None:
        self.wall_first_tick_s = round(time.monotonic() - self._wall_start, 3)
        self.sim_start_s = round(self._sim_now(), 3)

    def document(self) -> dict[str, Any]:
        """Return the status document as it stands (as it stood at completion, once complete)."""
        if self._frozen is not None:
            return dict(self._frozen)
        document = {
            "tree": self._tree_file,
            "status": self.status.name,
            "ticks": self.ticks,
            "wall_first_tick_s": self.wall_first_tick_s,
            "sim_start_s": self.sim_start_s,
            "sim_end_s": round(self._sim_now(), 3),
            "wall_duration_s": round(time.monotonic() - self._wall_start, 3),
            "nodes": dict(self.nodes),
            "running": list(self.running),
            "complete": self.complete,
        }
        if self._entries is not None and len(self._entries):
            document["entries"] = self._entries.final()
        if self.startup:
            document["startup"] = dict(self.startup)
        return document

    def write(self) -> None:
        """Write the document to the status file (no-op without one)."""
        if self._path is not None:
            write_json_atomically(self._path, self.document())
