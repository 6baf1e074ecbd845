"""The mission's processes: which programs start, in which order, with which parameters.

The one description both ``sar-tree run`` and ``launch/tree.launch.py`` start
from (no ROS imported here). Each caller fills a :class:`MissionSettings` from its own
options, :func:`mission_processes` turns it into :class:`Process` descriptions, and the
caller only translates those: ``sar-tree run`` into ``--ros-args`` command lines for its
supervisor (:func:`ros_arguments`), the launch file into ``launch_ros.actions.Node`` actions
(``parameters=[*params_files, parameters]``).

What the two genuinely do differently is a setting, not a second list:

- Both write a run's files (``trace_file``, ``status_file``, and the apps' own) into a
  folder of that run (:attr:`MissionSettings.run_folder`): ``sar-tree run`` into its
  ``--report-dir``, the launch into its ``report_dir`` argument or, by default, a new
  folder under ``$ROS_HOME/sar_runs/`` (:func:`new_run_folder`), so a mission never
  inherits an earlier one's results.
- The launch's ``nav2:=bringup`` starts Nav2 beside the mission, which can take a while next
  to Gazebo: it sets ``nav2_timeout_wall_s`` to :data:`BRINGUP_NAV2_TIMEOUT_S`. The embedded
  simulator, and a Nav2 that ``sar-tree run --no-sim`` expects already running, keep the
  runner's own bound (its default, or the mission parameter file's).
- The apps' processes (:attr:`sar_framework.app.App.processes`) take their files from
  :attr:`MissionSettings.extra` (``sar-tree run``'s app options, the launch's arguments);
  a label in :attr:`MissionSettings.disabled` does not start.

The robot count is a setting too (:attr:`MissionSettings.robots`). By default one robot,
unnamed: its runner in the root namespace, its files in the run folder. Named robots
(``sar-tree run --robots N``/``--fleet FILE``, the launch's ``robots``/``fleet_file``) share
one simulator (its ``fleet_file``) and the apps' shared processes; each has its runner, and
its own copy of the apps' ``per_robot`` processes, in ``/<name>``, with its files in
``RUN/<name>/`` and its spawn pose as ``initial_pose`` (plus what its apps add,
:attr:`sar_framework.app.App.robot_parameters`).
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from datetime import datetime, timezone
from pathlib import Path
from typing import Any, Protocol

import yaml

ParamValue = bool | int | float | str | list[bool] | list[int] | list[float] | list[str]
"""A ROS parameter value as both ``--ros-args -p`` and launch_ros take it."""

BRINGUP_NAV2_TIMEOUT_S = 90.0
"""The runner's bound on the Nav2 start-up when nav2_bringup starts beside the mission."""


RUN_FILES = {"trace_file": "trace.jsonl", "status_file": "status.json"}
"""A run's files in its folder, by the parameter that names each."""


def runs_root() -> Path:
    """``$ROS_HOME/sar_runs`` (``~/.ros/sar_runs`` when ROS_HOME is unset)."""
    home = os.environ.get("ROS_HOME") or os.path.join(os.path.expanduser("~"), ".ros")
    return Path(home) / "sar_runs"


def new_run_folder(root: Path | None = None) -> Path:
    """Create and return a folder of its own for one run: ``ROOT/YYYYmmdd-HHMMSS-ffffff``.

    Args:
        root: Where run folders go (default :func:`runs_root`).

    Returns:
        A new, empty folder (a suffix is added should the name be taken).
    """
    root = runs_root() if root is None else root
    root.mkdir(parents=True, exist_ok=True)
    stamp = datetime.now(timezone.utc).strftime("%Y%m%d-%H%M%S-%f")
    for attempt in range(1000):
        folder = root / (stamp if attempt == 0 else f"{stamp}-{attempt}")
        try:
            folder.mkdir()
        except FileExistsError:
            continue
        return folder
    raise FileExistsError(f"no free run folder under {root}")


@dataclass(frozen=True)
class Robot:
    """One robot of a run.

    Attributes:
        name: Its namespace (``robot1``); "" for the one robot of a run that names none
            (root namespace, its files in the run folder, its pose from the parameters).
        x: Spawn x, metres (map frame).
        y: Spawn y, metres.
        yaw: Spawn heading, radians.
    """

    name: str = ""
    x: float = 0.0
    y: float = 0.0
    yaw: float = 0.0


ONE_ROBOT = (Robot(),)
"""The robots of a run that names none."""


@dataclass(frozen=True)
class MissionSettings:
    """What a mission starts, whoever starts it (``sar-tree run`` or ``ros2 launch``).

    Empty strings and None leave a parameter unset: the process keeps its own default.

    Attributes:
        tree: The tree file (runner, recorder).
        params_file: The mission parameter file (the runner's params file; the recorder's),
            or "" for none (a tree that uses no app needs none).
        use_sim_time: The servers and the runner follow ``/clock``.
        simulator: Start the embedded simulator (``sar-sim``).
        speed: The simulator's speed factor (None: the simulator's default).
        trace_file: The simulator's JSON Lines trace.
        run_folder: The run's folder, where the apps' processes write their files ("":
            their own defaults).
        disabled: Labels of processes that do not start (``--no-detect-server``).
        exit_on_completion: The runner ends when the mission is complete.
        watch_tree: The runner reloads the tree when its file changes.
        status_file: The runner's JSON status file.
        nav2_timeout_wall_s: The runner's bound on the Nav2 start-up.
        tick_rate_hz: The runner's tick rate (over the parameter file's).
        plugin_paths: Extra plugin locations for the runner (the recorder keeps their files).
        record: Start the recorder writing this MCAP file.
        extra: Process label -> parameters set last (``sar-tree run --sim-param`` ...).
        robots: The robots (:data:`ONE_ROBOT` by default); named robots each run in
            their namespace with their files in ``run_folder/<name>/``.
        fleet_file: The simulator's fleet file (named robots' names and spawn poses).
        node_kinds: The tree's node kinds (an app may start a process only for a tree that
            uses one of its leaves).
    """

    tree: str
    params_file: str = ""
    use_sim_time: bool = True
    simulator: bool = True
    speed: float | None = None
    trace_file: str = ""
    run_folder: str = ""
    disabled: frozenset[str] = frozenset()
    exit_on_completion: bool = True
    watch_tree: bool = False
    status_file: str = ""
    nav2_timeout_wall_s: float | None = None
    tick_rate_hz: float | None = None
    plugin_paths: tuple[str, ...] = ()
    record: str = ""
    extra: Mapping[str, Mapping[str, ParamValue]] = field(default_factory=dict)
    robots: tuple[Robot, ...] = ONE_ROBOT
    fleet_file: str = ""
    node_kinds: frozenset[str] = frozenset()

    @property
    def named_robots(self) -> bool:
        """Whether the robots are named (each in its namespace), not the one unnamed robot."""
        return any(robot.name for robot in self.robots)

    def robot_folder(self, robot: Robot) -> Path:
        """Where ``robot``'s status, events, trace and report go: the run folder, or its own."""
        folder = Path(self.run_folder or Path(self.status_file).parent)
        return folder / robot.name if robot.name else folder


@dataclass(frozen=True)
class Process:
    """One process of the mission.

    Attributes:
        label: Short name: ``sar-tree run``'s progress lines and log file (``runner.log``).
        executable: The installed console script (``lib/sar_framework/<executable>``), or
            "" for a program this package does not install (an app's own, started as
            ``python -m`` :attr:`module` everywhere).
        module: The Python module ``python -m`` runs for the same program.
        params_files: ROS parameter files, in order (before :attr:`parameters`).
        parameters: ROS parameters, set after the files.
        namespace: The ROS namespace its nodes live in (a fleet's robot), "" for the root.
        python_path: Folders :attr:`module` is imported from, put before ``PYTHONPATH``
            (an app's package that is not installed, beside its tree).
    """

    label: str
    executable: str
    module: str
    params_files: tuple[str, ...] = ()
    parameters: dict[str, ParamValue] = field(default_factory=dict)
    namespace: str = ""
    python_path: tuple[str, ...] = ()

    @property
    def name(self) -> str:
        """``robot1/runner`` in a namespace, else the label (log files, progress lines)."""
        return f"{self.namespace}/{self.label}" if self.namespace else self.label


def _set(parameters: dict[str, ParamValue], name: str, value: ParamValue | None) -> None:
    """Set ``name`` unless ``value`` is None or an empty string (the process's default)."""
    if value is not None and value != "":
        parameters[name] = value


def recorder(settings: MissionSettings) -> Process | None:
    """``sar-mission-recorder``, first: it sees the mission from its first message."""
    if not settings.record:
        return None
    parameters: dict[str, ParamValue] = {
        "output": settings.record, "tree": settings.tree, "params_file": settings.params_file}
    _set(parameters, "plugin_path", os.pathsep.join(settings.plugin_paths))
    return Process("recorder", "sar-mission-recorder", "sar_framework.recording", (), parameters)


def simulator(settings: MissionSettings) -> Process | None:
    """``sar-sim``, the embedded Nav2 stand-in (it publishes ``/clock``)."""
    if not settings.simulator:
        return None
    parameters: dict[str, ParamValue] = {}
    _set(parameters, "speed", None if settings.speed is None else float(settings.speed))
    _set(parameters, "trace_file", settings.trace_file)
    _set(parameters, "fleet_file", settings.fleet_file)
    return Process("sim", "sar-sim", "sar_framework.sim", (), parameters)


def runner(settings: MissionSettings) -> Process | None:
    """``sar-mission-runner``, last: the servers it calls are starting already."""
    parameters: dict[str, ParamValue] = {
        "tree": settings.tree, "use_sim_time": settings.use_sim_time,
        "exit_on_completion": settings.exit_on_completion}
    if settings.watch_tree:
        parameters["watch_tree"] = True
    _set(parameters, "status_file", settings.status_file)
    _set(parameters, "nav2_timeout_wall_s", settings.nav2_timeout_wall_s)
    _set(parameters, "tick_rate_hz", settings.tick_rate_hz)
    _set(parameters, "plugin_path", os.pathsep.join(settings.plugin_paths))
    files = (settings.params_file,) if settings.params_file else ()
    return Process("runner", "sar-mission-runner", "sar_framework.runner.node", files,
                   parameters)


class ProcessSource(Protocol):
    """What starts processes beside the runner: an app (:class:`sar_framework.app.App`)."""

    processes: Callable[[MissionSettings], list[Process]] | None
    recorded_topics: tuple[tuple[str, str], ...]
    process_kinds: tuple[Any, ...]  # AppProcess: its label, per_robot
    robot_parameters: Callable[[MissionSettings, Robot, int], Mapping[str, ParamValue]] | None


BUILDERS: tuple[Callable[[MissionSettings], Process | None], ...] = (recorder, simulator)
"""The core's processes before the apps' and the runner, in start order; each returns None
when it does not start."""


def app_processes(settings: MissionSettings, apps: Sequence[ProcessSource]) -> list[Process]:
    """The apps' processes, in start order, without those ``settings.disabled`` names."""
    return [p for app in apps if app.processes is not None
            for p in app.processes(settings) if p.label not in settings.disabled]


def _per_robot(apps: Sequence[ProcessSource]) -> set[str]:
    """The labels of the apps' processes each named robot starts its own of."""
    return {kind.label for app in apps for kind in app.process_kinds if kind.per_robot}


def robot_processes(settings: MissionSettings, apps: Sequence[ProcessSource], robot: Robot,
                    index: int) -> list[Process]:
    """A robot's own processes: a named robot's app processes and runner in ``/<name>``.

    The unnamed robot has its runner alone (its apps' processes are the run's).

    Args:
        settings: What the mission starts.
        apps: The tree's apps.
        robot: The robot.
        index: Its place among the robots.
    """
    own = replace(settings, status_file=str(settings.robot_folder(robot) / "status.json")
                  if robot.name else settings.status_file)
    labels = _per_robot(apps) if robot.name else set()
    processes = [replace(p, namespace=robot.name)
                 for p in app_processes(own, apps) if p.label in labels]
    tree_runner = runner(own)
    assert tree_runner is not None
    parameters = dict(tree_runner.parameters)
    if robot.name:
        parameters.update({"initial_pose.x": robot.x, "initial_pose.y": robot.y,
                           "initial_pose.yaw": robot.yaw})
    for app in apps:
        if app.robot_parameters is not None:
            parameters.update(app.robot_parameters(settings, robot, index))
    return [*processes, replace(tree_runner, namespace=robot.name, parameters=parameters)]


def mission_processes(settings: MissionSettings,
                      apps: Sequence[ProcessSource] = ()) -> list[Process]:
    """The mission's processes in start order (the runners last), each with its parameters.

    Args:
        settings: What the mission starts (its robots among it).
        apps: The tree's apps: their processes start after the core's, before the runners
            (a named robot's own copies in its namespace).

    Returns:
        One description per process; ``settings.extra`` is applied last, by label (every
        robot's runner takes ``extra["runner"]``).
    """
    built = [build(settings) for build in BUILDERS]
    shared = _per_robot(apps) if settings.named_robots else set()
    built += [p for p in app_processes(settings, apps) if p.label not in shared]
    robots = [p for i, robot in enumerate(settings.robots)
              for p in robot_processes(settings, apps, robot, i)]
    built += [p for p in robots if p.label != "runner"]
    built += [p for p in robots if p.label == "runner"]
    topics = [f"{name} {kind}" for app in apps for name, kind in app.recorded_topics]
    return [with_extra(with_app_topics(p, topics), settings) for p in built if p is not None]


def with_app_topics(process: Process, topics: list[str]) -> Process:
    """The recorder with the apps' topics (``app_topics``: ``"NAME TYPE"`` each) to keep."""
    if process.label != "recorder" or not topics:
        return process
    return replace(process, parameters={**process.parameters, "app_topics": topics})


def with_extra(process: Process, settings: MissionSettings) -> Process:
    """``process`` with ``settings.extra`` for its label set last."""
    extra = settings.extra.get(process.label, {})
    return replace(process, parameters={**process.parameters, **extra})


# -- --ros-args ---------------------------------------------------------------------------
def _scalar(value: bool | int | float | str, *, in_list: bool = False) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return ".nan"
        if math.isinf(value):
            return ".inf" if value > 0 else "-.inf"
        text = repr(value)
        mantissa, e, exponent = text.partition("e")
        return text if "." in mantissa else f"{mantissa}.0{e}{exponent}"
    if not in_list and value and value.strip() == value:
        try:
            if yaml.safe_load(value) == value:
                return value  # reads back as this string: as a user would type it
        except yaml.YAMLError:
            pass
    return "'" + value.replace("'", "''") + "'"


def ros_value(value: ParamValue) -> str:
    """``value`` as the text of ``-p NAME:=TEXT`` that rcl reads back as ``value``.

    Args:
        value: A parameter value.

    Returns:
        YAML: ``true``, ``2``, ``2.0``, a plain or single-quoted string, a flow list.
    """
    if isinstance(value, list):
        return "[" + ", ".join(_scalar(item, in_list=True) for item in value) + "]"
    return _scalar(value)


def ros_arguments(process: Process) -> list[str]:
    """Everything after ``--ros-args`` for ``process``: its params files, then ``-p``.

    Args:
        process: The process description.

    Returns:
        ``["-r", "__ns:=/NS", "--params-file", FILE, ..., "-p", "NAME:=VALUE", ...]``
        (the namespace only for a process in one).
    """
    arguments: list[str] = []
    if process.namespace:
        arguments += ["-r", f"__ns:=/{process.namespace}"]
    for file in process.params_files:
        arguments += ["--params-file", file]
    for name, value in process.parameters.items():
        arguments += ["-p", f"{name}:={ros_value(value)}"]
    return arguments
