"""The runner's hot reload: the tree file read again and swapped in between two ticks.

Two triggers, one path (:meth:`TreeReloader.reload`):

- the service ``~/reload`` (``std_srvs/srv/Trigger``, ``/sar_mission_runner/reload``):
  its response says ``success`` and, as ``message``, what changed or every diagnostic;
- with the runner parameter ``watch_tree`` (``sar-tree run --reload``), the tree file and
  every file it includes, polled on the wall clock: a change that has stayed put for one
  poll (an editor's save is complete) reloads the tree once.

The new file is validated and built, and its new behaviours set up, before anything of
the running tree changes (:func:`sar_framework.engine.reloading.hot_swap.prepare_swap`); an
invalid file, a plugin that cannot be built or a ``setup`` that raises refuses the reload
and the mission goes on as it was. The service and the watcher run on the runner's
executor, as the tick does, so a swap always falls between two ticks. Each swap is a
``tree_swapped`` event and each refusal a ``reload_refused`` one (the console,
``events.jsonl``, mission.json and the recording show them). The mission's completion
mode stays the one resolved at start-up. A complete mission is not reloaded.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

from sar_framework.engine.api import LoadedTree
from sar_framework.events.event import EventKind
from sar_framework.mission.completion import ending_one_shot
from sar_framework.runner.entry_values import EntryTracker, writers_of

if TYPE_CHECKING:
    import py_trees
    from rclpy.node import Node

    from sar_framework.engine.reloading.hot_swap import HotSwap
    from sar_framework.events.emitter import EventEmitter
    from sar_framework.runner.status_file import StatusFileWriter
    from sar_framework.runner.tree_status import TreeStatusPublisher

#: How often the watched files are looked at (wall seconds).
WATCH_PERIOD_S = 0.5
#: The service's name, under the runner node's name.
SERVICE = "~/reload"

Signature = tuple[tuple[str, int, int], ...]


def tree_files(tree: str, plugin_paths: tuple[str, ...] = ()) -> list[Path]:
    """The tree file and every file it includes (the file alone when it does not load)."""
    from sar_framework.engine.api import validate

    try:
        files = list(validate(tree, plugin_paths=plugin_paths).files)
    except Exception:  # a watcher must never fail: watch the file itself then
        files = []
    return files or [Path(tree).resolve()]


def signature(files: list[Path]) -> Signature:
    """What the files look like now: path, modification time and size (-1: missing)."""
    found = []
    for path in files:
        try:
            stat = os.stat(path)
            found.append((str(path), stat.st_mtime_ns, stat.st_size))
        except OSError:
            found.append((str(path), -1, -1))
    return tuple(found)


class TreeReloader:
    """Reloads a running tree on request (service) or on change (watcher).

    Args:
        node: The runner node (service, timer, behaviours' ``setup``).
        tree_file: The tree file.
        plugin_paths: Extra plugin locations.
        context: The shared objects the tree was built with (the apps' objects...).
        events: The mission's event emitter.
        current: Returns the tree ticking now.
        complete: Whether the mission is complete (then nothing is reloaded).
        adopt: Makes the runner tick the swapped tree (called between ticks).
        watch: Poll the tree file and its includes, and reload on change.
    """

    def __init__(self, node: Node, tree_file: str, plugin_paths: tuple[str, ...],
                 context: Mapping[str, Any], events: EventEmitter, *,
                 current: Callable[[], LoadedTree], complete: Callable[[], bool],
                 adopt: Callable[[HotSwap], None], watch: bool = False) -> None:
        from rclpy.clock import Clock, ClockType
        from std_srvs.srv import Trigger

        self._node = node
        self._tree_file = tree_file
        self._plugin_paths = plugin_paths
        self._context = context
        self._events = events
        self._current = current
        self._complete = complete
        self._adopt = adopt
        self.swaps = 0
        self.refusals = 0
        self._service = node.create_service(Trigger, SERVICE, self._on_request)
        self._files: list[Path] = []
        self._seen: Signature = ()
        self._pending: Signature | None = None
        if watch:
            self._files = tree_files(tree_file, plugin_paths)
            self._seen = signature(self._files)
            self._timer = node.create_timer(WATCH_PERIOD_S, self._poll,
                                            clock=Clock(clock_type=ClockType.STEADY_TIME))

    def reload(self) -> tuple[bool, str]:
        """Read the tree file again and swap it in; say what changed or why not.

        Returns:
            Whether the tree was swapped, and one line: the summary or the diagnostics.
        """
        from sar_framework.engine.diagnostics import TreeLoadError
        from sar_framework.engine.reloading.hot_swap import prepare_swap

        logger = self._node.get_logger()
        if self._complete():
            return self._refuse("the mission is complete")
        try:
            prepared = prepare_swap(self._current(), self._tree_file, self._context,
                                    plugin_paths=self._plugin_paths)
        except TreeLoadError as err:
            return self._refuse("; ".join(str(d) for d in err.diagnostics) or str(err))
        except Exception as err:  # a plugin that raised outside the builder's wrapping
            return self._refuse(f"cannot build it: {type(err).__name__}: {err}")
        for behaviour in prepared.fresh:
            try:
                behaviour.setup(node=self._node, events=self._events)
            except Exception as err:
                return self._refuse(f"setup of {behaviour.name} failed: "
                                    f"{type(err).__name__}: {err}")
        swap = prepared.commit()
        self._adopt(swap)
        self.swaps += 1
        message = f"Tree swapped from {self._tree_file}: {swap.summary.line()}"
        self._events.emit(EventKind.TREE_SWAPPED, message=message)
        logger.info(message)
        return True, message

    def _refuse(self, why: str) -> tuple[bool, str]:
        self.refusals += 1
        message = f"Reload of {self._tree_file} refused, the tree goes on: {why}"
        self._events.emit(EventKind.RELOAD_REFUSED, message=message)
        # Info, like the swap: the mission is unharmed (sar-tree run prints the event once).
        self._node.get_logger().info(message)
        return False, message

    def _on_request(self, _request: Any, response: Any) -> Any:
        response.success, response.message = self.reload()
        return response

    def _poll(self) -> None:
        now = signature(self._files)
        if now == self._seen:
            self._pending = None
            return
        if now != self._pending:  # still being written: look again next time
            self._pending = now
            return
        self._pending = None
        self.reload()
        files = tree_files(self._tree_file, self._plugin_paths)  # includes may change
        # What was read is what `now` saw: a save made during the reload differs from it
        # and is loaded at the next settled poll.
        self._seen = now if files == self._files else signature(files)
        self._files = files


def follow_swap(tree: py_trees.trees.BehaviourTree, swap: HotSwap, *,
                status_writer: StatusFileWriter, status_publisher: TreeStatusPublisher,
                events: EventEmitter) -> None:
    """Make the ticking tree and the runner's observers follow a swap (between ticks).

    Args:
        tree: The ticking tree (its root is replaced when the root was rebuilt).
        swap: The swap done.
        status_writer: The status file writer.
        status_publisher: The tree status publisher.
        events: The event emitter (learns the new nodes' uids and kinds).
    """
    loaded = swap.tree
    if tree.root is not loaded.root:
        tree.root = loaded.root
    entries = EntryTracker(loaded.entries, writers_of(loaded.entries.values()))
    status_writer.retarget(loaded.spec, loaded.behaviours,
                           getattr(ending_one_shot(loaded.spec), "uid", None), entries)
    status_publisher.retarget(loaded.spec, loaded.behaviours, entries)
    kinds = {n.uid: n.kind for n in loaded.spec.nodes()}
    events.know({uid: (b, kinds.get(uid, "")) for uid, b in loaded.behaviours.items()})
