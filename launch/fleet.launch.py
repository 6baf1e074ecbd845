"""A fleet's search-and-rescue mission under ``ros2 launch``: N robots in one simulator.

    ros2 launch sar_framework fleet.launch.py [robots:=3 | fleet_file:=FILE]
        [tree:=fleet_search] [params_file:=...] [survivors_file:=...] [speed:=...]
        [report_dir:=DIR] [tick_rate_hz:=...]

Starts what ``sar-tree run TREE --robots N`` / ``--fleet FILE`` starts (the description is
:mod:`sar_framework.mission.fleet_processes`): the embedded simulator with the fleet file,
the base's report server and, when the tree bids for zones, the zone coordinator (both in
the root namespace), and per robot in ``/<name>`` a detect server and a runner whose
``initial_pose`` and home are its spawn pose. ``robots:=N`` writes the fleet file of N
spawn places near the base into the run's folder (``report_dir``, by default a new
``$ROS_HOME/sar_runs/<UTC time>/``); each robot's status and events go to its sub-folder.
The launch ends when every runner has ended: exit 0 when every mission succeeded.
"""

from __future__ import annotations

from pathlib import Path

from launch.actions import (
    DeclareLaunchArgument,
    EmitEvent,
    LogInfo,
    OpaqueFunction,
    RegisterEventHandler,
)
from launch.event_handlers import OnProcessExit
from launch.events import Shutdown
from launch.substitutions import LaunchConfiguration
from sar_plugins.sar.params import zone_positions

from launch import LaunchContext, LaunchDescription
from sar_framework.app import tree_apps
from sar_framework.engine.api import validate
from sar_framework.mission.fleet_processes import (
    FLEET_FILE,
    FleetSettings,
    fleet_processes,
    tree_uses_coordinator,
)
from sar_framework.mission.params_file import read_params_file
from sar_framework.mission.processes import RUN_FILES, MissionSettings, new_run_folder
from sar_framework.orchestrate.fleet_inputs import read_members
from sar_framework.ros.launch_nodes import package_file, process_node
from sar_framework.sim.params import DEFAULT_MAP_YAML, SPEED
from sar_framework.sim.spawn_poses import write_fleet_file
from sar_framework.sim.world import load_world

ARGUMENTS = [
    DeclareLaunchArgument("robots", default_value="3",
                          description="How many robots, spawned near the base (ignored with "
                          "fleet_file)."),
    DeclareLaunchArgument("fleet_file", default_value="",
                          description="A fleet file naming the robots and their spawn poses "
                          "(docs/how-to/fleet.md); empty: robots:=N."),
    DeclareLaunchArgument("tree", default_value="fleet_search.yaml",
                          description="Behaviour tree, the same for every robot: a path, or "
                          "a file in the package's trees/."),
    DeclareLaunchArgument("params_file", default_value="config/mission_params.yaml",
                          description="Mission parameters (zones, base station, tick rate)."),
    DeclareLaunchArgument("survivors_file", default_value="config/survivors.yaml",
                          description="Survivor table the detect servers answer from."),
    DeclareLaunchArgument("report_dir", default_value="",
                          description="This run's folder; empty: a new "
                          "$ROS_HOME/sar_runs/<time>/."),
    DeclareLaunchArgument("speed", default_value=str(SPEED.default),
                          description=f"The simulator's speed: "
                          f"{SPEED.description.split(';')[0]}."),
    DeclareLaunchArgument("tick_rate_hz", default_value="",
                          description="Override the tick rate of params_file (empty: keep)."),
]


def fleet_settings(context: LaunchContext) -> FleetSettings:
    """What the fleet starts, from the launch arguments (the fleet file written if asked)."""
    def arg(name: str) -> str:
        return LaunchConfiguration(name).perform(context)

    folder = (Path(arg("report_dir")).expanduser().absolute() if arg("report_dir")
              else new_run_folder())
    folder.mkdir(parents=True, exist_ok=True)
    params_file = package_file(arg("params_file"))
    mission = read_params_file(params_file).values
    tree = package_file(arg("tree"), "trees")
    if arg("fleet_file"):
        fleet_file = Path(package_file(arg("fleet_file")))
    else:
        from sar_framework.sim.occupancy import load_map

        base = (float(mission.get("base_station.x", 0.0)),
                float(mission.get("base_station.y", 0.0)))
        fleet_file = write_fleet_file(
            folder / FLEET_FILE, int(arg("robots")), base, load_map(DEFAULT_MAP_YAML),
            load_world().robot.footprint_radius, zones=list(zone_positions(mission).values()))
    spec = validate(tree).spec
    kinds = [node.kind for node in spec.nodes()] if spec is not None else []
    settings = MissionSettings(
        tree=tree, params_file=params_file, speed=float(arg("speed")),
        run_folder=str(folder), trace_file=str(folder / RUN_FILES["trace_file"]),
        tick_rate_hz=float(arg("tick_rate_hz")) if arg("tick_rate_hz") else None,
        extra={"detect": {"survivors_file": package_file(arg("survivors_file"))}})
    return FleetSettings(settings, str(fleet_file), read_members(fleet_file), str(folder),
                         coordinator=tree_uses_coordinator(kinds),
                         zone_order=tuple(mission.get("zone_order") or ()),
                         apps=tuple(tree_apps(tree)))


def launch_setup(context: LaunchContext) -> list:
    """The fleet's processes as Nodes; the launch ends once every runner has ended."""
    fleet = fleet_settings(context)
    actions: list = [LogInfo(msg=f"sar_framework: a fleet of {len(fleet.robots)} "
                                 f"({', '.join(r.name for r in fleet.robots)}); this run's "
                                 f"files are in {fleet.run_dir}/")]
    ended: dict[str, int] = {}
    runners = len(fleet.robots)

    def on_runner_exit(event: object, exit_context: LaunchContext) -> list | None:
        ended[str(id(getattr(event, "action", None)))] = event.returncode
        if exit_context.is_shutdown or len(ended) < runners:
            return None
        failed = [code for code in ended.values() if code != 0]
        if failed:
            raise RuntimeError(f"{len(failed)} of {runners} runners did not succeed "
                               f"(exit codes {failed})")
        return [EmitEvent(event=Shutdown(reason="every robot's mission is complete"))]

    for process in fleet_processes(fleet):
        node = process_node(process)
        actions.append(node)
        if process.label == "runner":
            actions.append(RegisterEventHandler(
                OnProcessExit(target_action=node, on_exit=on_runner_exit)))
    return actions


def generate_launch_description() -> LaunchDescription:
    """The fleet: simulator, base, coordinator, and per robot a detect server and a runner."""
    return LaunchDescription([*ARGUMENTS, OpaqueFunction(function=launch_setup)])
