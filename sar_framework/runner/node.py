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
:data:`.mission_runner.CANCEL_GRACE_S`). A repeated signal is ignored: a terminal's Ctrl-C
reaches every process of the group and ``ros2 launch`` forwards it once more. The tick loop,
completion and the way out are :mod:`.mission_runner`'s.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Callable, Mapping, Sequence
from typing import TYPE_CHECKING, Any

from sar_framework.mission.params import ParamsError, create_params_node
from sar_framework.mission.params_file import (
    KeyLocation,
    check_params_file,
    params_files_from_args,
)
from sar_framework.ros.teardown import bounded_teardown
from sar_framework.ros.tf_topics import TF_REMAP_ARGS
from sar_framework.run_clock import run_started
from sar_framework.runner.mission_runner import EXIT_STOPPED, MissionRunner
from sar_framework.runner.settings import RunnerSettings, read_runner_settings
from sar_framework.runner.status_file import (
    startup_failure_document,
    write_json_atomically,
)
from sar_framework.runner.tree_context import tree_context
from sar_framework.stop_signals import StopSignals

if TYPE_CHECKING:
    from rclpy.node import Node

    from sar_framework.app import App, AppRun

NODE_NAME = "sar_mission_runner"
EXIT_CONFIG = 2
EXIT_STARTUP = 3


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
        with bounded_teardown():  # Fast DDS's participant teardown can hang
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
