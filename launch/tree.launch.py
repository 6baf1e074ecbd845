"""Any tree under ``ros2 launch``: Nav2, the processes of the tree's apps, and the runner.

    ros2 launch sar_framework tree.launch.py tree:=my_tree.yaml [nav2:=bringup|embedded]
        [params_file:=...] [tick_rate_hz:=...] [map:=...] [spawn:=X,Y[,YAW]]
        [nav2_params_file:=...] [use_sim_time:=true|false] [rviz:=true|false] [speed:=...]
        [record:=FILE.mcap] [report_dir:=DIR] [reload:=true] [set:="NAME=VALUE ..."]
        [robots:=N | fleet_file:=FILE] [app_params:="LABEL.NAME:=VALUE ..."]

``nav2:=bringup`` (the default, for the robot or Gazebo) includes nav2_bringup's
``bringup_launch.py`` with our map and Nav2 parameters; ``nav2:=embedded`` starts this
package's simulator (``sar-sim``) instead, like Nav2's loopback simulation. The launch ends
when the runner ends: exit 0 when the mission succeeded, non-zero otherwise. ``record``
adds the recorder (``sar-mission-recorder``), which writes the mission to a rosbag2-compatible
MCAP file and closes it when the launch shuts down. ``reload:=true`` makes the runner swap the
tree in between ticks whenever its file changes (``sar-tree run --reload``;
docs/how-to/hot-reload.md). ``robots:=N`` or ``fleet_file:=FILE`` names the robots, as
``sar-tree run --robots N``/``--fleet FILE`` do: one simulator serves them all, each robot
has its runner (and its apps' per-robot processes) in ``/<name>``, its files in
``<run folder>/<name>/``; the launch then ends once every runner has ended, with
``sar-tree run``'s reports (each robot's, and ``fleet.json``, ``fleet.png``).

Like ``sar-tree run``, every launch writes its run's files (the runner's status and events,
the simulator's trace, the apps' processes' files) into a folder of its own: ``report_dir``,
or by default a new ``$ROS_HOME/sar_runs/<UTC time>/``, and the report ``sar-tree run``
writes beside them. A tree without an app needs no parameter file. ``app_params`` sets
parameters of the apps' processes (``LABEL.NAME:=VALUE``: NAME of the process labelled
LABEL), as ``sar-tree run --LABEL-param`` does; an app's own launch file fills it
(``search_and_rescue.launch.py``). Process output carries colour codes only when the
launch's own output is a terminal.

File arguments default to this package's share folder (ament index). A path that exists
(absolute, or relative to the working directory) is used as given; otherwise it is taken
from the package share, and ``tree`` may name a file in its trees/ (``search_and_rescue``).
Every process names its own nodes (no process-wide ``__node`` remap: the runner's process
also holds BasicNavigator's node, the simulator's holds amcl and bt_navigator).

Which of this package's processes start, and with which parameters, is not written here:
the arguments fill a ``MissionSettings`` and :mod:`sar_framework.mission.processes` (the
description ``sar-tree run`` starts from too) says the rest; this file adds what only a
launch does (nav2_bringup, RViz, ending with the runner).
"""

from __future__ import annotations

import functools
import shlex
import time
from pathlib import Path

from ament_index_python.packages import get_package_share_directory
from launch.actions import (
    DeclareLaunchArgument,
    EmitEvent,
    IncludeLaunchDescription,
    LogInfo,
    OpaqueFunction,
    RegisterEventHandler,
)
from launch.conditions import IfCondition
from launch.event_handlers import OnProcessExit
from launch.events import Shutdown
from launch.launch_description_sources import PythonLaunchDescriptionSource
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node

from launch import LaunchContext, LaunchDescription
from sar_framework.app import tree_apps
from sar_framework.engine.api import validate
from sar_framework.mission.processes import (
    BRINGUP_NAV2_TIMEOUT_S,
    ONE_ROBOT,
    RUN_FILES,
    MissionSettings,
    ParamValue,
    mission_processes,
    new_run_folder,
)
from sar_framework.mission.runner_params import DEFAULT_TREE
from sar_framework.orchestrate.config import entry_values
from sar_framework.orchestrate.launch_report import (
    write_launch_report,
    write_robots_launch_report,
)
from sar_framework.ros.launch_nodes import package_file, process_node
from sar_framework.sim.params import DEFAULT_MAP_YAML, SPEED

NAV2_MODES = ("bringup", "embedded")

ARGUMENTS = [
    DeclareLaunchArgument("nav2", default_value="bringup", choices=list(NAV2_MODES),
                          description="bringup: nav2_bringup (robot, Gazebo); embedded: "
                          "this package's simulator."),
    DeclareLaunchArgument("tree", default_value=Path(DEFAULT_TREE).name,
                          description="Behaviour tree: a path, or a file in the package's "
                          "trees/."),
    DeclareLaunchArgument("params_file", default_value="",
                          description="Mission parameters (tick rate; the app's own); "
                          "empty: the tree's app's file, none for a tree that uses no app."),
    DeclareLaunchArgument("app_params", default_value="",
                          description="Parameters of the apps' processes, 'LABEL.NAME:=VALUE' "
                          "separated by spaces (shell quoting), as sar-tree run --LABEL-param."),
    DeclareLaunchArgument("report_dir", default_value="",
                          description="This run's folder (status.json, events.jsonl, "
                          "trace.jsonl, the apps' files); empty: a new "
                          "$ROS_HOME/sar_runs/<time>/."),
    DeclareLaunchArgument("tick_rate_hz", default_value="",
                          description="Override the tick rate of params_file (empty: keep)."),
    DeclareLaunchArgument("map", default_value="",
                          description="map_server map file (map_saver's yaml) for Nav2: "
                          "bringup's map server, or the simulator's map (embedded); empty: "
                          f"maps/{DEFAULT_MAP_YAML.name}."),
    DeclareLaunchArgument("spawn", default_value="",
                          description="Where the robot starts on the map: X,Y[,YAW] in metres "
                          "and radians; empty: the simulator's default (embedded)."),
    DeclareLaunchArgument("nav2_params_file", default_value="config/nav2_params.yaml",
                          description="Nav2 parameters (ROSbot; bringup)."),
    DeclareLaunchArgument("use_sim_time", default_value="true",
                          description="Follow /clock (Gazebo, the simulator); false on the "
                          "real robot."),
    DeclareLaunchArgument("speed", default_value=str(SPEED.default),
                          description=f"The simulator's speed: {SPEED.description.split(';')[0]} "
                          "(embedded)."),
    DeclareLaunchArgument("rviz", default_value="false",
                          description="Start RViz with Nav2's default view (bringup)."),
    DeclareLaunchArgument("reload", default_value="false",
                          description="Swap the tree in between ticks whenever its file or an "
                          "include changes (the runner's watch_tree; docs/how-to/hot-reload.md)."),
    DeclareLaunchArgument("set", default_value="",
                          description="Initial values of entries the tree declares, "
                          "NAME=VALUE each, separated by spaces (set:=\"battery=50 "
                          "label='two words'\"; sar-tree run --set)."),
    DeclareLaunchArgument("record", default_value="",
                          description="Record the mission into this MCAP file "
                          "(rosbag2-compatible; sar-mission-recorder); empty: no recording."),
    DeclareLaunchArgument("robots", default_value="",
                          description="Name N robots, spawned by the tree's app's choice "
                          "(embedded); empty: one robot in the root namespace."),
    DeclareLaunchArgument("fleet_file", default_value="",
                          description="A fleet file naming the robots and their spawn poses "
                          "(embedded; docs/how-to/fleet.md)."),
    # launch's own escalation bound: a process still running this long after SIGINT gets
    # SIGTERM. Launch's default of 5 s cut short a loaded machine's flush of traces and
    # recordings; an idle stop takes about 1 s (benchmarks/soak_launch_ctrl_c.py).
    DeclareLaunchArgument("sigterm_timeout", default_value="15",
                          description="Seconds a process may take to stop after SIGINT "
                          "before launch sends it SIGTERM."),
]


def end_with_runner(event: object, context: LaunchContext, *, settings: MissionSettings,
                    apps: list, started: float) -> list | None:
    """Write the run's report, then shut the launch down; fail it when the mission failed.

    The report (mission.json, mission.png, tree.svg in the run's folder) is the one
    ``sar-tree run`` writes. ``ros2 launch`` exits 1 when a launch action raises, so a
    runner exit code other than 0 becomes the launch's failure, with the reason in its log.
    A runner stopped by the launch's own shutdown (Ctrl-C) is not a failure.
    """
    code = event.returncode
    if context.is_shutdown:
        return None
    written = write_launch_report(settings, apps, code, started)
    said = LogInfo(msg=f"sar_framework: report in {Path(settings.status_file).parent}/ "
                       f"({', '.join(p.name for p in written)})")
    if code != 0:
        said.execute(context)  # before the failure ends the launch
        raise RuntimeError(f"sar-mission-runner exited with code {code}: the mission did "
                           "not succeed")
    return [said, EmitEvent(event=Shutdown(reason="the mission is complete"))]


def end_with_runners(event: object, context: LaunchContext, *, robot: str,
                     ended: dict[str, int], settings: MissionSettings, apps: list,
                     started: float) -> list | None:
    """Named robots: once every runner ended, write the reports and shut the launch down.

    The reports are ``sar-tree run``'s: each robot's in its folder, the run's
    ``fleet.json`` and ``fleet.png``; the launch fails when the run's verdict is not SUCCESS.
    """
    ended[robot] = event.returncode
    if context.is_shutdown or len(ended) < len(settings.robots):
        return None
    verdict, written = write_robots_launch_report(settings, apps, ended, started)
    folder = Path(settings.run_folder)
    said = LogInfo(msg=f"sar_framework: report in {settings.run_folder}/ "
                       f"({', '.join(p.name for p in written if p.parent == folder)}; each "
                       "robot's report in its folder)")
    if verdict.status != "SUCCESS":
        said.execute(context)
        raise RuntimeError(f"the robots' mission did not succeed: {verdict.status}: "
                           f"{verdict.reason}")
    return [said, EmitEvent(event=Shutdown(reason="every robot's mission is complete"))]


def named_robots(folder: Path, fleet_file: str, count: str, params_file: str,
                 apps: list) -> tuple[str, tuple]:
    """The fleet file and its robots (``robots:=N`` writes one in ``folder``), or none."""
    from sar_framework.mission.params_file import read_params_file
    from sar_framework.orchestrate.robots import FLEET_FILE, read_robots, spawn_around
    from sar_framework.sim.occupancy import load_map
    from sar_framework.sim.params import sim_default
    from sar_framework.sim.spawn_poses import write_fleet_file

    if fleet_file:
        path = Path(package_file(fleet_file))
    elif count:
        values = read_params_file(params_file).values if params_file else {}
        centre, places = spawn_around(values, apps)
        path = write_fleet_file(folder / FLEET_FILE, int(count), centre,
                                load_map(DEFAULT_MAP_YAML), sim_default("robot_radius"),
                                destinations=places)
    else:
        return "", ONE_ROBOT
    return str(path), read_robots(path)


def sim_place(map_arg: str, spawn_arg: str) -> dict[str, ParamValue]:
    """The simulator's map and spawn pose, checked as ``sar-tree run --map --spawn`` are."""
    from sar_framework.sim.occupancy import MapError, load_map, spawn_problem
    from sar_framework.sim.params import SPAWN_NAMES, parse_pose, sim_default

    map_yaml = package_file(map_arg) if map_arg else str(DEFAULT_MAP_YAML)
    try:
        grid = load_map(map_yaml)
    except MapError as err:
        raise RuntimeError(f"map:={map_arg}: {err}") from None
    try:
        pose = parse_pose(spawn_arg) if spawn_arg else None
    except ValueError as err:
        raise RuntimeError(f"spawn:={err}") from None
    x, y = pose[:2] if pose else (sim_default("spawn_x"), sim_default("spawn_y"))
    problem = spawn_problem(grid, x, y)
    if problem:
        raise RuntimeError(f"spawn:={spawn_arg or '(default)'}: {problem} on {map_yaml}")
    return {**({"map_yaml": map_yaml} if map_arg else {}),
            **dict(zip(SPAWN_NAMES, pose or (), strict=False))}


def mission_settings(context: LaunchContext) -> MissionSettings:
    """What the mission starts, from the launch arguments (file arguments resolved)."""
    def arg(name: str) -> str:
        return LaunchConfiguration(name).perform(context)

    embedded = arg("nav2") == "embedded"
    record = arg("record")
    folder = (Path(arg("report_dir")).expanduser().absolute() if arg("report_dir")
              else new_run_folder())
    folder.mkdir(parents=True, exist_ok=True)
    files = {name: str(folder / file) for name, file in RUN_FILES.items()}
    entries: dict[str, list[str]] = {}
    for entry in shlex.split(arg("app_params")):
        label, _, setting = entry.partition(".")
        entries.setdefault(label, []).append(setting)
    servers: dict[str, dict[str, ParamValue]] = {
        label: entry_values(settings) for label, settings in entries.items()}
    if arg("set"):
        servers["runner"] = {**servers.get("runner", {}), "set": arg("set")}
    if embedded and (arg("map") or arg("spawn")):
        servers["sim"] = {**servers.get("sim", {}), **sim_place(arg("map"), arg("spawn"))}
    tree = package_file(arg("tree"), "trees")
    apps = tree_apps(tree)
    params = arg("params_file") or next((f for f in (a.default_params_file() for a in apps)
                                         if f), "")
    params = package_file(params) if params else ""
    fleet_file, robots = named_robots(folder, arg("fleet_file"), arg("robots"), params, apps)
    spec = validate(tree).spec
    return MissionSettings(
        tree=tree,
        params_file=params,
        use_sim_time=arg("use_sim_time").lower() in ("true", "1", "yes"),
        simulator=embedded,
        speed=float(arg("speed")),
        run_folder=str(folder),
        extra=servers,
        trace_file=files["trace_file"] if embedded else "",
        status_file=files["status_file"],
        exit_on_completion=True,
        watch_tree=arg("reload").lower() in ("true", "1", "yes"),
        # Nav2 bring-up next to Gazebo can take a while; the simulator is up in seconds.
        nav2_timeout_wall_s=None if embedded else BRINGUP_NAV2_TIMEOUT_S,
        tick_rate_hz=float(arg("tick_rate_hz")) if arg("tick_rate_hz") else None,
        record=str(Path(record).expanduser().absolute()) if record else "",
        robots=robots, fleet_file=fleet_file,
        node_kinds=frozenset(n.kind for n in spec.nodes()) if spec is not None else frozenset(),
    )


def launch_setup(context: LaunchContext) -> list:
    """Build the actions once the arguments are known: Nav2's side, then the processes."""
    started = time.monotonic()
    settings = mission_settings(context)
    apps = tree_apps(settings.tree)
    actions: list = [LogInfo(msg=f"sar_framework: this run's files are in "
                                 f"{Path(settings.status_file).parent}/")]
    if not settings.simulator:
        bringup = Path(get_package_share_directory("nav2_bringup"))
        actions.append(IncludeLaunchDescription(
            PythonLaunchDescriptionSource(str(bringup / "launch" / "bringup_launch.py")),
            launch_arguments={
                "map": package_file(LaunchConfiguration("map").perform(context)
                                    or f"maps/{DEFAULT_MAP_YAML.name}"),
                "params_file": package_file(
                    LaunchConfiguration("nav2_params_file").perform(context)),
                "use_sim_time": str(settings.use_sim_time),
                "autostart": "true",
            }.items(),
        ))
        actions.append(Node(
            package="rviz2", executable="rviz2", name="rviz2",
            arguments=["-d", str(bringup / "rviz" / "nav2_default_view.rviz")],
            parameters=[{"use_sim_time": settings.use_sim_time}],
            condition=IfCondition(LaunchConfiguration("rviz")), output="screen"))
    ended: dict[str, int] = {}  # named robots: each runner's exit code
    for process in mission_processes(settings, apps):
        node = process_node(process)
        actions.append(node)
        if process.label == "runner":
            actions.append(RegisterEventHandler(OnProcessExit(
                target_action=node, on_exit=functools.partial(
                    end_with_runners, robot=process.namespace, ended=ended, settings=settings,
                    apps=apps, started=started)
                if settings.named_robots else functools.partial(
                    end_with_runner, settings=settings, apps=apps, started=started))))
    return actions


def generate_launch_description() -> LaunchDescription:
    """Nav2 (bringup or embedded), the apps' processes and the runner, with the arguments above."""
    return LaunchDescription([*ARGUMENTS, OpaqueFunction(function=launch_setup)])
