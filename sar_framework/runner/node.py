"""``sar-mission-runner``: load a tree file and tick it on ROS 2 until done or Ctrl-C.

::

    sar-mission-runner --ros-args --params-file config/mission_params.yaml
        -p tree:=trees/search_and_rescue.yaml -p use_sim_time:=true   (one line)

Start-up, in order; each step is bounded and fails with one clear message:

1. every ``--params-file`` is checked in pure Python (file:line:col messages) before rcl
   parses it (:mod:`sar_framework.mission.params_file`);
2. the node ``sar_mission_runner`` is created with auto-declared overrides; the runner's
   parameters (:mod:`.settings`) are read;
3. the tree is checked, and each app it uses (:mod:`sar_framework.app`) reads its own
   parameters and gives its context objects;
4. AMCL is seeded and Nav2 awaited (``seed_amcl``; :mod:`.nav2_startup`); meanwhile, while
   BasicNavigator sleeps, the tree is loaded with the apps' context objects and set up
   with ``node=`` (bounded by ``setup_timeout_wall_s``);
   (``~/reload`` and ``watch_tree`` swap a new one in between ticks: :mod:`.reload`)
5. the tree is ticked at ``tick_rate_hz`` on a timer of the node (ROS time, so it follows
   ``/clock``).

The status file's ``startup`` lists when each start-up step was done, in wall seconds of
the run (:mod:`sar_framework.run_clock`): ``runner_started_s``, ``tree_ready_s`` and the
Nav2 steps (:data:`.nav2_startup.STEPS`, ``_s`` appended).

When the mission is *complete* follows the ``completion`` parameter or the tree file's
``completion`` key (:mod:`sar_framework.mission.completion`): ``end`` (the default) when
the tree reaches its declared end (the root fails, or succeeds as the one_shot on its
final path latches); ``once`` at the root's first SUCCESS or FAILURE; ``rest`` when the
tree is at rest; ``forever`` never. A complete mission is not ticked again. On
completion the runner emits its ``completion`` event (status SUCCESS or FAILURE) and logs
``Mission complete.`` or ``Mission failed (...)`` for humans, once; with
``exit_on_completion`` it then ends, otherwise it stays up (not ticking; its figures
frozen at completion) until SIGINT.

Other processes read the runner's events, never its log (:mod:`.mission_events`): on
``/sar_mission/events`` and, with a ``status_file``, in ``events.jsonl`` beside it.

Exit codes: 0 complete with SUCCESS, 1 complete with FAILURE, 2 a parameter or tree error,
3 a start-up failure (Nav2 never ready, tree setup failed or timed out), 4 still not complete
after ``sim_timeout_s`` of ticking on the node's ROS clock (the status file's ``running``
names the nodes it stopped). A shutdown
requested by SIGINT/SIGTERM is a clean exit 0 even before the mission was complete (the
status file says so: ``complete`` is false), as ``ros2 launch`` expects of its processes;
whoever sent the signal knows the mission was interrupted.

On SIGINT the timer stops, running leaves are terminated (``root.stop(INVALID)``, which
cancels Nav2 goals in flight), the executor spins briefly so the cancel requests leave the
process, and only then are the node and the context shut down (bounded by
:data:`CANCEL_GRACE_S`). A repeated signal is ignored: a terminal's Ctrl-C reaches every
process of the group and ``ros2 launch`` forwards it once more.
"""

from __future__ import annotations

import functools
import sys
import time
from collections.abc import Callable, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import py_trees
from py_trees.common import Status

from sar_framework.events.event import EVENT_TOPIC_NAME, EventKind, in_namespace
from sar_framework.mission.completion import ending_one_shot, resolve_completion
from sar_framework.mission.params import ParamsError, create_params_node
from sar_framework.mission.params_file import (
    KeyLocation,
    check_params_file,
    params_files_from_args,
)
from sar_framework.ros.delivery import deliver
from sar_framework.ros.tf_topics import TF_REMAP_ARGS
from sar_framework.run_clock import run_started
from sar_framework.runner.entry_values import EntryTracker, writers_of
from sar_framework.runner.mission_events import mission_events
from sar_framework.runner.reasons import reason_line
from sar_framework.runner.reload import TreeReloader, follow_swap
from sar_framework.runner.settings import RunnerSettings, read_runner_settings
from sar_framework.runner.status_file import (
    StatusFileWriter,
    startup_failure_document,
    write_json_atomically,
)
from sar_framework.runner.tree_context import tree_context
from sar_framework.runner.tree_status import STATUS_TOPIC_NAME, TreeStatusPublisher
from sar_framework.runner.tree_ticker import publish_snapshots
from sar_framework.stop_signals import StopSignals

if TYPE_CHECKING:
    from rclpy.executors import Executor
    from rclpy.node import Node
    from rclpy.timer import Timer

    from sar_framework.app import App, AppRun
    from sar_framework.engine.api import LoadedTree
    from sar_framework.engine.reloading.hot_swap import HotSwap

NODE_NAME = "sar_mission_runner"
EXIT_SUCCESS = 0
EXIT_FAILURE = 1
EXIT_CONFIG = 2
EXIT_STARTUP = 3
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
        from sar_framework.runner.tree_ticker import implementation_name

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
                         [in_namespace(name, self.node.get_namespace())
                          for name in (STATUS_TOPIC_NAME, EVENT_TOPIC_NAME)], DELIVERY_WALL_S):
            self.logger.warning("a subscriber of the status or event topic did not receive "
                                f"everything within {DELIVERY_WALL_S:g} s")
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


def create_runner_node(**kwargs: Any) -> Node:
    """The runner's node, with Nav2 bringup's TF remapping (:mod:`sar_framework.ros.tf_topics`).

    Started in a namespace (``--ros-args -r __ns:=/robot1``), its leaves find their servers
    by relative names and read TF from ``/robot1/tf``, as a namespaced Nav2 stack does.

    Args:
        **kwargs: Further ``rclpy.node.Node`` arguments (``context``...).
    """
    return create_params_node(NODE_NAME, cli_args=TF_REMAP_ARGS, **kwargs)


class _StartupError(Exception):
    """The runner cannot start: its exit code, the step that failed and why."""

    def __init__(self, code: int, step: str, message: str) -> None:
        super().__init__(message)
        self.code, self.step, self.message = code, step, message


def _check_params_files(argv: Sequence[str]) -> tuple[list[str], dict[str, KeyLocation]]:
    """Check every ``--params-file`` in pure Python; merge where keys are set."""
    files = params_files_from_args(argv)
    locations: dict[str, KeyLocation] = {}
    for file in files:
        locations.update(check_params_file(file))
    return files, locations


def start_apps(node: Node, apps: Sequence[App], source: str,
               locations: Mapping[str, KeyLocation]) -> list[AppRun]:
    """Start the tree's apps on the runner's node: each reads its parameters.

    Raises:
        ParamsError: An app's parameter is missing or wrong.
    """
    from sar_framework.app import AppRun

    return [app.start(node, source, locations) if app.start is not None else AppRun()
            for app in apps]


def run(argv: Sequence[str] | None = None) -> int:
    """Run the mission runner.

    Args:
        argv: The command line (``sys.argv`` when None), ROS arguments included.

    Returns:
        The exit code (see the module docstring).
    """
    import rclpy
    import rclpy.logging
    from rclpy.experimental import EventsExecutor
    from rclpy.signals import SignalHandlerOptions

    from sar_framework import load_tree
    from sar_framework.app import AppError, tree_apps
    from sar_framework.engine.diagnostics import TreeLoadError
    from sar_framework.runner.nav2_startup import (
        Nav2StartupError,
        StartupInterrupted,
        seed_amcl_and_wait_for_nav2,
    )

    wall_start = run_started()  # sar-tree run's start when it started us, else now
    startup = {"runner_started_s": round(time.monotonic() - wall_start, 3)}

    def done(step: str) -> None:  # a start-up step, for the status file
        startup[f"{step}_s"] = round(time.monotonic() - wall_start, 3)

    args = list(sys.argv if argv is None else argv)
    early_logger = rclpy.logging.get_logger(NODE_NAME)
    try:
        files, locations = _check_params_files(args)
    except ParamsError as err:
        early_logger.error(str(err))
        return EXIT_CONFIG

    stop = StopSignals()
    rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
    stop.install()
    node: Node | None = None
    runner: MissionRunner | None = None
    settings: RunnerSettings | None = None
    build: Callable[[], None] | None = None  # the tree's build, once the node is made

    def fail(code: int, step: str, message: str) -> int:
        (node.get_logger() if node is not None else early_logger).error(message)
        if settings is not None and settings.status_file:
            write_json_atomically(settings.status_file, startup_failure_document(
                settings.tree, step, message, time.monotonic() - wall_start))
        return code

    try:
        source = files[0] if files else "parameters"
        try:
            node = create_runner_node()
        except ValueError as err:  # e.g. -p NAME:=[] (an untyped empty list)
            return fail(EXIT_CONFIG, "parameters", f"{source}: {err}")
        try:
            # A runner setting missing from the files came from a -p override or a default.
            settings = read_runner_settings(node, source="parameters", locations=locations)
            apps = start_apps(node, tree_apps(settings.tree, settings.plugin_paths), source,
                              locations)
        except ParamsError as err:
            return fail(EXIT_CONFIG, "parameters", str(err))
        except AppError as err:
            return fail(EXIT_CONFIG, "tree", str(err))
        logger = node.get_logger()
        context = tree_context(node, apps)

        def build() -> None:  # the tree, loaded and set up
            nonlocal runner
            try:
                loaded = load_tree(settings.tree, context=context,
                                   plugin_paths=settings.plugin_paths,
                                   initial_values=settings.initial_values)
            except TreeLoadError as err:
                lines = "\n".join(str(d) for d in err.diagnostics) or str(err)
                raise _StartupError(EXIT_CONFIG, "tree",
                                    f"cannot load {settings.tree}:\n{lines}") from err
            except Exception as err:  # a plugin that raised outside the loader's wrapping
                raise _StartupError(EXIT_CONFIG, "tree", f"cannot build {settings.tree}: "
                                    f"{type(err).__name__}: {err}") from err
            runner = MissionRunner(node, settings, apps, loaded, stop=stop,
                                   wall_start=wall_start, context=context)
            runner.status_writer.startup = startup
            try:
                runner.setup()
            except RuntimeError as err:
                raise _StartupError(EXIT_STARTUP, "setup", str(err)) from err
            done("tree_ready")

        # As serve.py's: /clock, /tf and feedback wake the runner at the simulator's update
        # rate; 1.8 s of CPU per mission instead of 2.3 s with SingleThreadedExecutor (100 Hz).
        executor = EventsExecutor()
        executor.add_node(node)
        try:
            if settings.seed_amcl:  # the tree is built while BasicNavigator sleeps
                # ... and the node spins meanwhile: the set-up tree's timers (a fleet robot's
                # heartbeat) and its clients' discovery go on until the first tick
                seed_amcl_and_wait_for_nav2(
                    pose=settings.initial_pose, timeout_s=settings.nav2_timeout_wall_s,
                    use_sim_time=settings.use_sim_time, should_stop=lambda: bool(stop),
                    logger=logger, on_step=done, meanwhile=build,
                    idle=lambda step: executor.spin_once(timeout_sec=step))
            else:
                build()
            assert runner is not None
            if stop:
                return EXIT_STOPPED
            return runner.run(executor)
        finally:
            executor.remove_node(node)
            executor.shutdown(timeout_sec=0.0)
    except _StartupError as err:
        return fail(err.code, err.step, err.message)
    except Nav2StartupError as err:
        if runner is None and build is not None:  # a bad tree says so, whatever Nav2 does
            try:
                build()
            except _StartupError as tree_err:
                return fail(tree_err.code, tree_err.step, tree_err.message)
        return fail(EXIT_STARTUP, "nav2", str(err))
    except StartupInterrupted:
        (node.get_logger() if node is not None else early_logger).info(
            "stopped while waiting for Nav2")
        return EXIT_STOPPED
    finally:
        if runner is not None and runner.tree.node is not None:
            runner.shutdown()  # destroys the node
        elif node is not None:
            node.destroy_node()
        rclpy.try_shutdown()


def main(argv: Sequence[str] | None = None) -> None:
    """Console entry point (``sar-mission-runner``)."""
    sys.exit(run(argv))


if __name__ == "__main__":
    main()
