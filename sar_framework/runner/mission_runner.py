"""The runner's tick loop: a loaded tree ticked on its node until complete or stopped.

:class:`MissionRunner` wraps the tree (py_trees_ros's, else the fallback of
:mod:`.tree_ticker`), writes the status file and the tree status each tick, tells the
mission's events, decides completion (:mod:`sar_framework.mission.completion`) and the
``sim_timeout_s`` bound on the node's ROS clock, and on the way out delivers its last
messages and halts running leaves (:meth:`MissionRunner.run`). Start-up (parameters, apps,
Nav2, the tree's build) is :mod:`.node`'s.
"""

from __future__ import annotations

import functools
import time
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import py_trees
from py_trees.common import Status

from sar_framework.events.event import EVENT_TOPIC_NAME, EventKind, in_namespace
from sar_framework.mission.completion import ending_one_shot, resolve_completion
from sar_framework.ros.delivery import deliver
from sar_framework.runner.entry_values import EntryTracker, writers_of
from sar_framework.runner.mission_events import mission_events
from sar_framework.runner.reasons import reason_line
from sar_framework.runner.reload import TreeReloader, follow_swap
from sar_framework.runner.settings import RunnerSettings
from sar_framework.runner.status_file import StatusFileWriter
from sar_framework.runner.tree_status import STATUS_TOPIC_NAME, TreeStatusPublisher
from sar_framework.runner.tree_ticker import publish_snapshots
from sar_framework.stop_signals import StopSignals

if TYPE_CHECKING:
    from rclpy.executors import Executor
    from rclpy.node import Node
    from rclpy.timer import Timer

    from sar_framework.app import AppRun
    from sar_framework.engine.api import LoadedTree
    from sar_framework.engine.reloading.hot_swap import HotSwap

EXIT_SUCCESS = 0
EXIT_FAILURE = 1
EXIT_STOPPED = 0
EXIT_SIM_TIMEOUT = 4
#: How long the executor keeps spinning after running leaves were stopped.
CANCEL_GRACE_S = 0.5
#: Warn when ``use_sim_time`` is set and no tick came within this many wall seconds.
NO_CLOCK_WARNING_S = 5.0
#: How long a finished runner waits for its listeners to receive its last messages.
DELIVERY_WALL_S = 3.0
#: How often a finished mission kept alive re-publishes its final tree snapshot.
SNAPSHOT_PERIOD_S = 1.0


class MissionRunner:
    """Ticks a loaded tree on a node and reports its progress.

    Args:
        node: The runner node (also given to every behaviour's ``setup``).
        settings: The runner's parameters.
        apps: The tree's apps, started (their events and status fields).
        loaded: The loaded tree.
        stop: The stop flag set by signals.
        wall_start: ``time.monotonic()`` when the process started.
        context: The shared objects the tree was built with (a reload builds with them).
    """

    def __init__(self, node: Node, settings: RunnerSettings, apps: Sequence[AppRun],
                 loaded: LoadedTree, *, stop: StopSignals, wall_start: float,
                 context: Mapping[str, Any] | None = None) -> None:
        from sar_framework.runner.tree_ticker import create_behaviour_tree

        self.node = node
        self.settings = settings
        self.apps = tuple(apps)
        self.loaded = loaded
        self.stop = stop
        self.logger = node.get_logger()
        self.finished = False
        self.sim_timed_out = False
        self._announced = False
        self._snapshot_timer: Timer | None = None
        self.completion, self.completion_why = resolve_completion(settings.completion,
                                                                  loaded.spec)
        self.tree = create_behaviour_tree(loaded.root)
        self.events, self._events_file = mission_events(node, settings, loaded, self.apps,
                                                        wall_start)
        entries = EntryTracker(loaded.entries, writers_of(loaded.entries.values()))
        self.status_writer = StatusFileWriter(
            settings.tree, loaded.spec, loaded.behaviours,
            lambda: node.get_clock().now().nanoseconds / 1e9,
            path=settings.status_file or None, wall_start=wall_start,
            completion=self.completion, emitter=self.events, entries=entries,
            end_uid=getattr(ending_one_shot(loaded.spec), "uid", None),
        )
        self.tree.visitors.append(self.status_writer)
        self.tree.add_post_tick_handler(self._after_tick)
        self.status_publisher = TreeStatusPublisher(
            node, loaded.spec, loaded.behaviours, extra=self._app_status,
            complete=lambda: self.status_writer.complete, entries=entries).attach(self.tree)
        self.reloader = TreeReloader(  # the ~/reload service; watch_tree: the file watched
            node, settings.tree, settings.plugin_paths, context or {}, self.events,
            current=lambda: self.loaded, complete=lambda: self.status_writer.complete,
            adopt=self._adopt, watch=settings.watch_tree)

    def _app_status(self) -> dict[str, Any]:
        """The apps' fields of the tree status, as they are now."""
        fields: dict[str, Any] = {}
        for app in self.apps:
            if app.status is not None:
                fields.update(app.status())
        return fields

    def _adopt(self, swap: HotSwap) -> None:
        """Tick a swapped tree from the next tick on (see :mod:`.reload`)."""
        self.loaded = swap.tree
        follow_swap(self.tree, swap, status_writer=self.status_writer,
                    status_publisher=self.status_publisher, events=self.events)

    def setup(self) -> None:
        """Set up every behaviour with the node (bounded).

        Raises:
            RuntimeError: Setup failed or timed out; the message says which behaviour.
        """
        try:
            self.tree.setup(node=self.node, events=self.events,
                            timeout=self.settings.setup_timeout_wall_s)
        except Exception as err:
            raise RuntimeError(f"tree setup failed: {type(err).__name__}: {err}") from err

    def run(self, executor: Executor) -> int:
        """Tick until the tree finishes (with ``exit_on_completion``) or a stop request.

        Args:
            executor: An executor the node is added to.

        Returns:
            The exit code.
        """
        from sar_framework.runner.tree_ticker import implementation_name, snapshot_topics

        period_ms = 1000.0 / self.settings.tick_rate_hz
        self.tree.tick_tock(period_ms=period_ms)
        ticking = (f"Ticking {self.settings.tree} at {self.settings.tick_rate_hz:g} Hz "
                   f"({implementation_name(self.tree)} tree, {len(self.loaded.behaviours)} "
                   f"nodes); completion: {self.completion} ({self.completion_why})")
        self.events.emit(EventKind.STARTED, message=ticking)
        self.logger.info(ticking)
        started = time.monotonic()
        warned = False
        while not self.stop and not self.finished:
            executor.spin_once(timeout_sec=0.1)
            if (not warned and self.status_writer.ticks == 0 and self.settings.use_sim_time
                    and time.monotonic() - started > NO_CLOCK_WARNING_S):
                warned = True
                self.logger.warning(f"no tick within {NO_CLOCK_WARNING_S:g} s: use_sim_time is "
                                    "true; is /clock being published?")
        if self.stop:
            self.logger.info(f"{self.stop.name}: stopping the tree")
        elif not deliver(self.node, executor,
                         [*(in_namespace(name, self.node.get_namespace())
                            for name in (STATUS_TOPIC_NAME, EVENT_TOPIC_NAME)),
                          *snapshot_topics(self.tree)], DELIVERY_WALL_S):
            self.logger.warning("a subscriber of the status, event or snapshot topics did "
                                f"not receive everything within {DELIVERY_WALL_S:g} s")
        self._halt(executor)
        return self.exit_code()

    def exit_code(self) -> int:
        """Return 0/1 for a complete mission (SUCCESS/FAILURE), 4 past ``sim_timeout_s``, else 0."""
        if self.sim_timed_out:
            return EXIT_SIM_TIMEOUT
        if not self.status_writer.complete:
            return EXIT_STOPPED
        return EXIT_SUCCESS if self.status_writer.status == Status.SUCCESS else EXIT_FAILURE

    def shutdown(self) -> None:
        """Shut the behaviours down and destroy the node (the tree owns it now)."""
        try:
            self.tree.shutdown()
        except Exception as err:  # a behaviour's shutdown must not hide the exit code
            self.logger.error(f"tree shutdown: {type(err).__name__}: {err}")
        if self._events_file is not None:
            self._events_file.close()

    def _after_tick(self, tree: py_trees.trees.BehaviourTree) -> None:
        changed = self.status_writer.after_tick(tree)
        for record in self.status_writer.new_reasons:
            self.events.emit(EventKind(record["what"]),
                             source=self.loaded.behaviours.get(record["uid"]),
                             message=record["message"])
            self.logger.warning(reason_line(record))
        self.status_writer.new_reasons.clear()
        if changed and self.settings.print_tree:
            self.logger.info("\n" + py_trees.display.unicode_tree(tree.root, show_status=True))
        if not self.status_writer.complete:
            self._check_sim_timeout()
            return
        if self.completion != "forever":
            self._stop_ticking()  # a finished mission is never ticked again
        if not self._announced:
            self._announced = True
            status = tree.root.status
            if status == Status.SUCCESS:
                verdict = "Mission complete."
            else:
                reasons = "; ".join(f"{f['name']}: {f['message']}"
                                    for f in self.status_writer.failures[-3:]) or "no reason given"
                verdict = f"Mission failed ({reasons})."
            self.events.emit(EventKind.COMPLETION, source=tree.root, status=status.name,
                             message=verdict)
            (self.logger.info if status == Status.SUCCESS else self.logger.error)(verdict)
        if self.settings.exit_on_completion:
            self.finished = True
        elif self.completion != "forever" and self._snapshot_timer is None:
            # Not ticked again, but still watched: py-trees-tree-watcher and its streams
            # keep receiving the final tree once a second.
            self._snapshot_timer = self.node.create_timer(
                SNAPSHOT_PERIOD_S, functools.partial(publish_snapshots, self.tree))

    def _check_sim_timeout(self) -> None:
        """End the run once the tree has ticked ``sim_timeout_s`` on its ROS clock."""
        bound = self.settings.sim_timeout_s
        started = self.status_writer.sim_start_s
        if bound <= 0 or started is None or self.sim_timed_out:
            return
        ticked = self.node.get_clock().now().nanoseconds / 1e9 - started
        if ticked >= bound:
            self.sim_timed_out = True
            self.finished = True
            self._stop_ticking()
            self.logger.error(f"sim_timeout_s: the mission is not complete after {ticked:.1f} "
                              f"s of ROS time (bound {bound:g} s); stopping the tree")

    def _stop_ticking(self) -> None:
        timer = getattr(self.tree, "timer", None)
        if timer is not None:
            timer.cancel()

    def _halt(self, executor: Executor) -> None:
        """Stop ticking, terminate running leaves, and let their cancel requests out."""
        self._stop_ticking()
        root = self.loaded.root
        running = [b.name for b in root.iterate() if b.status == Status.RUNNING and not b.children]
        if root.status != Status.INVALID:
            root.stop(Status.INVALID)  # terminate(): running leaves cancel their goals
        if running:
            self.logger.info(f"stopped running leaves: {', '.join(running)}")
            deadline = time.monotonic() + CANCEL_GRACE_S
            while time.monotonic() < deadline:
                executor.spin_once(timeout_sec=0.05)
        self.status_writer.write()
