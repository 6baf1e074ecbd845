"""The launch file, run through the real launch / launch_ros, and config/nav2_params.yaml.

With the ROS 2 stack built (``make setup`` with the overlay) the launch description is
evaluated by launch itself: arguments, the nav2_bringup include down to each Nav2 node's
parameters, the embedded mode, the tree lookup. Without it those tests skip with one line.
"""

from __future__ import annotations

import ast
import importlib.util
import itertools
import py_compile
from pathlib import Path

import pytest
import yaml

from sar_framework.mission import processes
from sar_framework.mission.params_file import check_params_file
from sar_framework.orchestrate.config import check_config, child_specs
from sar_framework.orchestrate.options import RunConfig
from sar_framework.sim.params import SPEED

REPO = Path(__file__).resolve().parents[2]
LAUNCH = REPO / "launch" / "search_and_rescue.launch.py"
TREE_LAUNCH = REPO / "launch" / "tree.launch.py"  # the neutral one the app's includes
NAV2 = REPO / "config" / "nav2_params.yaml"
TREE = REPO / "trees" / "search_and_rescue.yaml"
MISSION = REPO / "config" / "mission_params.yaml"
SURVIVORS = REPO / "config" / "survivors.yaml"
HAVE_LAUNCH = (importlib.util.find_spec("launch_ros") is not None
               and importlib.util.find_spec("nav2_common") is not None)
needs_launch = pytest.mark.skipif(
    not HAVE_LAUNCH, reason="real-stack tier: launch_ros / nav2_bringup not built (make setup "
    "with ../shared/ros-overlay or SAR_ROS_OVERLAY_SRC)")
NAV2_NODES = {"map_server", "amcl", "controller_server", "smoother_server", "planner_server",
              "behavior_server", "bt_navigator", "waypoint_follower", "velocity_smoother",
              "collision_monitor", "docking_server"}


@pytest.fixture(autouse=True)
def _ros_home(tmp_path, monkeypatch, launch_tmpdir):
    """A launch without report_dir makes a run folder under $ROS_HOME: keep it in tmp (and
    launch's launch_params_* files: ``launch_tmpdir``)."""
    monkeypatch.setenv("ROS_HOME", str(tmp_path / "ros_home"))


def declared_arguments(launch: Path = LAUNCH) -> dict[str, str]:
    found = {}
    for node in ast.walk(ast.parse(launch.read_text())):
        if isinstance(node, ast.Call) and getattr(node.func, "id", "") == "DeclareLaunchArgument":
            name = ast.literal_eval(node.args[0])
            defaults = [k.value for k in node.keywords if k.arg == "default_value"]
            found[name] = _literal(defaults[0]) if defaults else None
    return found


def _literal(node: ast.expr) -> str:
    """A literal's value; any other expression as its source text."""
    try:
        return ast.literal_eval(node)
    except ValueError:
        return ast.unparse(node)


def test_launch_files_compile(tmp_path):
    for launch in (LAUNCH, TREE_LAUNCH):
        py_compile.compile(str(launch), cfile=str(tmp_path / "launch.pyc"), doraise=True)


def test_declared_arguments_and_their_defaults():
    assert set(declared_arguments()) == {"survivors_file", "report_file"}  # the app's own
    declared = {**declared_arguments(TREE_LAUNCH), **declared_arguments()}
    assert set(declared) == {"nav2", "tree", "params_file", "survivors_file", "report_file",
                             "report_dir", "tick_rate_hz", "map", "spawn", "nav2_params_file",
                             "use_sim_time", "app_params",
                             "speed", "rviz", "record", "reload", "robots", "fleet_file",
                             "set", "sigterm_timeout"}
    assert declared["nav2"] == "bringup" and declared["use_sim_time"] == "true"
    assert declared["record"] == ""  # no recorder unless asked
    assert declared["reload"] == "false"  # the tree file is not watched unless asked
    assert declared["report_dir"] == ""  # a new folder per run
    assert declared["robots"] == declared["fleet_file"] == ""  # one robot, unnamed
    assert declared["tree"] == "Path(DEFAULT_TREE).name"  # the runner's
    assert declared["app_params"] == ""
    assert declared["map"] == declared["spawn"] == ""  # the simulator's own defaults
    for key in ("nav2_params_file", "survivors_file"):
        assert (REPO / declared[key]).is_file(), declared[key]
    # As sar-tree run's --params: none named, the tree's app's (none for a tree without one).
    assert declared["params_file"] == ""
    # The nodes' tables, not copies.
    assert declared["speed"] == "str(SPEED.default)"
    assert declared["report_file"] == "REPORT_FILE.default"
    assert SPEED.default == 20.0


# --- evaluated by launch itself ------------------------------------------------------------

def evaluate(**arguments: str) -> tuple[list, dict, object]:
    """Visit the launch description like LaunchService would, without starting processes.

    Returns the launch_ros Nodes (with substitutions performed in their launch context),
    the IncludeLaunchDescription launch arguments seen, by include file name, and the
    context.
    """
    from launch.actions import ExecuteProcess, IncludeLaunchDescription
    from launch.launch_description_sources import PythonLaunchDescriptionSource
    from launch.utilities import normalize_to_list_of_substitutions, perform_substitutions
    from launch_ros.actions import LoadComposableNodes, Node

    from launch import LaunchContext, LaunchDescription

    context = LaunchContext()
    source = PythonLaunchDescriptionSource(str(LAUNCH))
    top = IncludeLaunchDescription(source, launch_arguments=list(arguments.items()))
    nodes: list = []
    includes: dict = {}

    def walk(entities) -> None:
        for entity in entities:
            condition = getattr(entity, "condition", None)
            if condition is not None and not condition.evaluate(context):
                continue
            if isinstance(entity, Node):
                entity._perform_substitutions(context)  # what Node.execute does first
                nodes.append(entity)
                continue
            if isinstance(entity, ExecuteProcess | LoadComposableNodes):
                continue  # starts processes or calls a container: not run here
            if isinstance(entity, LaunchDescription):
                walk(entity.entities)
                continue
            children = entity.visit(context) or []
            if isinstance(entity, IncludeLaunchDescription):  # its location is resolved now
                name = Path(entity.launch_description_source.location).name
                includes[name] = {
                    perform_substitutions(context, normalize_to_list_of_substitutions(key)):
                        perform_substitutions(context, normalize_to_list_of_substitutions(value))
                    for key, value in entity.launch_arguments}
            walk(children)

    walk([top])
    return nodes, includes, context


def command_line(node, context) -> list[str]:
    """The node's arguments after its executable, substitutions performed."""
    from launch.utilities import perform_substitutions

    # What Node.execute puts in the locals: a name only for a node launched with name=.
    name = node.node_name.rsplit("/", 1)[-1]
    context.extend_locals({"ros_specific_arguments": {"ns": "__ns:=/",
                                                      "name": f"__node:={name}"}})
    return [perform_substitutions(context, part) for part in node.cmd[1:]]


def parameters(arguments: list[str], node: str = "") -> dict:
    """The ``--params-file`` sections for ``node`` (and ``/**``) and ``-p`` of a command line."""
    merged: dict = {}
    for flag, value in itertools.pairwise(arguments):
        if flag == "--params-file":
            for section, content in (yaml.safe_load(Path(value).read_text()) or {}).items():
                if section in ("/**", node, f"/{node}") and isinstance(content, dict):
                    merged.update(content.get("ros__parameters", {}))
        elif flag == "-p":
            name, _, text = value.partition(":=")
            merged[name] = yaml.safe_load(text)
    return merged


@needs_launch
def test_bringup_gives_every_nav2_node_our_params_map_and_sim_time():
    # One process per Nav2 node (bringup's use_composition:=False) so each has its command.
    nodes, includes, context = evaluate(use_sim_time="true", use_composition="False")
    bringup = includes["bringup_launch.py"]
    assert bringup["map"] == str(REPO / "maps" / "final_project_map.yaml")
    assert bringup["params_file"] == str(REPO / "config" / "nav2_params.yaml")
    assert bringup["use_sim_time"] == "True"
    assert "navigation_launch.py" in includes and "localization_launch.py" in includes
    ours = yaml.safe_load(NAV2.read_text())
    # A node without name= (controller_server) keeps its executable's default name.
    names = {node: node.node_name.rsplit("/", 1)[-1] for node in nodes}
    by_name = {node.node_executable if "unspecified" in name else name: node
               for node, name in names.items()}
    assert set(by_name) >= NAV2_NODES, sorted(by_name)
    for name in NAV2_NODES:
        params = parameters(command_line(by_name[name], context), name)
        assert params["use_sim_time"] is True, name
        for key, value in ours.get(name, {}).get("ros__parameters", {}).items():
            if key not in ("use_sim_time", "yaml_filename"):
                assert params[key] == value, (name, key)
    assert parameters(command_line(by_name["map_server"], context),
                      "map_server")["yaml_filename"] == \
        str(REPO / "maps" / "final_project_map.yaml")


@needs_launch
def test_embedded_runs_the_simulator_and_every_process_names_its_own_nodes():
    nodes, includes, context = evaluate(nav2="embedded", tree="search_and_rescue",
                                        tick_rate_hz="5")
    assert set(includes) == {"search_and_rescue.launch.py", "tree.launch.py"}  # no bringup
    assert [n.node_executable for n in nodes] == [
        "sar-sim", "sar-detect-survivor-server", "sar-report-survivor-server",
        "sar-mission-runner"]
    for node in nodes:
        assert node.node_package == "sar_framework"
        arguments = command_line(node, context)
        assert not any(a.startswith("__node:=") for a in arguments), arguments
    runner = parameters(command_line(nodes[-1], context), "sar_mission_runner")
    assert Path(runner["tree"]).resolve() == REPO / "trees" / "search_and_rescue.yaml"  # by name
    assert runner["tick_rate_hz"] == 5.0 and runner["exit_on_completion"] is True
    assert runner["zone_order"]  # the mission file from the package share


@needs_launch
def test_every_process_gets_time_to_stop_on_sigint_before_sigterm():
    """Launch's own 5 s cut a loaded simulator's stop short (SIGTERM, not a clean exit)."""
    from launch.utilities import perform_substitutions

    nodes, _, context = evaluate(nav2="embedded", tree="search_and_rescue")
    assert nodes
    for node in nodes:
        bound = perform_substitutions(context, node._ExecuteLocal__sigterm_timeout)
        assert float(bound) == 15.0, (node.node_executable, bound)
    assert float(perform_substitutions(context, nodes[0]._ExecuteLocal__sigterm_timeout)) \
        > 5.0  # launch's default


@needs_launch
def test_record_starts_the_recorder_writing_that_file(tmp_path):
    output = tmp_path / "x.mcap"
    nodes, _includes, context = evaluate(nav2="embedded", record=str(output))
    recorders = [n for n in nodes if n.node_executable == "sar-mission-recorder"]
    assert len(recorders) == 1, [n.node_executable for n in nodes]
    recorder = parameters(command_line(recorders[0], context), "sar_mission_recorder")
    assert recorder["output"] == str(output)
    assert Path(recorder["tree"]).resolve() == REPO / "trees" / "search_and_rescue.yaml"
    assert Path(recorder["params_file"]).resolve() == REPO / "config" / "mission_params.yaml"
    unrecorded, _includes, _context = evaluate(nav2="embedded")
    assert "sar-mission-recorder" not in [n.node_executable for n in unrecorded]


@needs_launch
def test_a_tree_path_that_exists_is_used_as_given(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "mine.yaml").write_text("format: 1\n")
    nodes, _includes, context = evaluate(nav2="embedded", tree="mine.yaml",
                                         use_sim_time="false")
    runner = parameters(command_line(nodes[-1], context), "sar_mission_runner")
    assert runner["tree"] == str(tmp_path / "mine.yaml")
    assert runner["use_sim_time"] is False


def run_files(**arguments: str) -> dict[str, str]:
    """The files one launch's processes write: the report log, status, trace."""
    nodes, _includes, context = evaluate(nav2="embedded", **arguments)
    by_exe = {n.node_executable: parameters(command_line(n, context)) for n in nodes}
    return {"report_file": by_exe["sar-report-survivor-server"]["report_file"],
            "status_file": by_exe["sar-mission-runner"]["status_file"],
            "trace_file": by_exe["sar-sim"]["trace_file"]}


@needs_launch
def test_two_launches_in_a_row_write_into_folders_of_their_own(tmp_path):
    """Regression: every launch shared ~/.ros/sar_reports.jsonl; the second mission counted
    the first one's survivors ('2 survivors already on record ... Repeated report')."""
    first, second = run_files(), run_files()
    root = tmp_path / "ros_home" / "sar_runs"
    for files in (first, second):
        folders = {Path(f).parent for f in files.values()}
        assert len(folders) == 1 and folders.pop().parent == root, files
        assert not Path(files["report_file"]).exists()  # nothing inherited
    assert Path(first["report_file"]).parent != Path(second["report_file"]).parent
    assert sorted(p.name for p in root.iterdir()) == sorted(
        Path(f["status_file"]).parent.name for f in (first, second))


@needs_launch
def test_reusing_a_report_log_is_explicit(tmp_path):
    shared = tmp_path / "shared.jsonl"
    first = run_files(report_file=str(shared))
    second = run_files(report_file=str(shared), report_dir=str(tmp_path / "mine"))
    assert first["report_file"] == second["report_file"] == str(shared)
    assert second["status_file"] == str(tmp_path / "mine" / "status.json")


@needs_launch
def test_process_output_has_no_colour_codes_when_not_a_terminal():
    """Regression: redirected ros2 launch output carried ESC[0m ... ESC[0m\r (emulate_tty)."""
    nodes, _includes, _context = evaluate(nav2="embedded")
    ours = [n for n in nodes if n.node_package == "sar_framework"]
    assert ours and not any(n.emulate_tty for n in ours)  # pytest's stdout is no terminal


# --- one description: the launch file and sar-tree run start the same processes --------------

def launched(report_dir: Path, **arguments: str) -> list[tuple[str, dict]]:
    """This package's processes as the launch starts them: executable, parameters."""
    nodes, _includes, context = evaluate(
        tree=str(TREE), params_file=str(MISSION), report_dir=str(report_dir), **arguments)
    return [(node.node_executable, parameters(command_line(node, context)))
            for node in nodes if node.node_package == "sar_framework"]


def run_children(report_dir: Path, **options: object) -> list[tuple[str, dict]]:
    """The processes ``sar-tree run`` starts: executable, parameters of its command line."""
    config = RunConfig(tree=str(TREE), params=str(MISSION), **options)
    inputs = check_config(config)
    return [(spec.executable, parameters(list(spec.ros_args)))
            for spec in child_specs(config, report_dir, inputs.places, apps=inputs.apps)]


def assert_same_but(launch: list, run: list, *, run_only: dict[str, dict],
                    launch_only: dict[str, dict] | None = None) -> None:
    """The same executables with the same parameters, but for the parameters named."""
    assert [executable for executable, _ in launch] == [executable for executable, _ in run]
    for (executable, by_launch), (_, by_run) in zip(launch, run, strict=True):
        assert {**by_launch, **run_only.get(executable, {})} == \
            {**by_run, **(launch_only or {}).get(executable, {})}, executable


@needs_launch
def test_launch_and_sar_tree_run_start_the_same_processes_with_the_same_parameters(tmp_path):
    record = str(tmp_path / "mission.mcap")
    launch = launched(tmp_path, nav2="embedded", survivors_file=str(SURVIVORS), speed="7.5",
                      tick_rate_hz="4", record=record)
    run = run_children(tmp_path, app_options={"--survivors": str(SURVIVORS)}, speed=7.5,
                       record=record, runner_params=["tick_rate_hz:=4.0"])
    assert [executable for executable, _ in run] == [
        "sar-mission-recorder", "sar-sim", "sar-detect-survivor-server",
        "sar-report-survivor-server", "sar-mission-runner"]
    assert run[-1][1]["tick_rate_hz"] == 4.0 and run[1][1]["speed"] == 7.5
    # Both write the run's files into the run's folder.
    assert_same_but(launch, run, run_only={})


@needs_launch
def test_with_nav2_bringup_the_runner_waits_longer_for_nav2_and_nothing_else_differs(tmp_path):
    launch = launched(tmp_path, nav2="bringup", use_sim_time="false",
                      survivors_file=str(SURVIVORS))
    run = run_children(tmp_path, sim=False,  # Nav2 already up
                       app_options={"--survivors": str(SURVIVORS)})
    assert launch[-1][1]["nav2_timeout_wall_s"] == processes.BRINGUP_NAV2_TIMEOUT_S
    assert "nav2_timeout_wall_s" not in run[-1][1]  # the runner's own bound (or the file's)
    assert_same_but(launch, run, run_only={}, launch_only={"sar-mission-runner": {
        "nav2_timeout_wall_s": processes.BRINGUP_NAV2_TIMEOUT_S}})


@needs_launch
def test_a_process_or_parameter_added_to_the_description_reaches_both(tmp_path, monkeypatch):
    def twin(settings: processes.MissionSettings) -> processes.Process:
        return processes.Process("twin", "sar-detect-survivor-server",
                                 "sar_plugins.sar.servers.detect_survivor_server", (),
                                 {"service_name": "/detect_again"})

    def simulator(settings: processes.MissionSettings) -> processes.Process | None:
        process = processes.simulator(settings)
        if process is not None:  # a list of strings a YAML reader would take for numbers
            process.parameters["blocked_areas"] = ["1:2:0.5", "zone_b"]
        return process

    builders = [simulator if b is processes.simulator else b for b in processes.BUILDERS]
    monkeypatch.setattr(processes, "BUILDERS", (*builders[:-1], twin, builders[-1]))
    launch = launched(tmp_path, nav2="embedded")
    run = run_children(tmp_path)
    for started in (launch, run):
        assert ("sar-detect-survivor-server", {"service_name": "/detect_again"}) in started
        assert dict(started)["sar-sim"]["blocked_areas"] == ["1:2:0.5", "zone_b"]
    assert len(launch) == len(run) == 5


# --- config/nav2_params.yaml --------------------------------------------------------------

@pytest.fixture(scope="module")
def nav2() -> dict:
    check_params_file(NAV2)  # a valid ROS 2 parameter file (rcl would accept it)
    return yaml.safe_load(NAV2.read_text())


def params(nav2: dict, *path: str) -> dict:
    section = nav2
    for key in path:
        section = section[key]
    return section["ros__parameters"]


def test_nav2_params_have_every_server(nav2):
    for server in ("amcl", "bt_navigator", "controller_server", "planner_server",
                   "behavior_server", "map_server", "velocity_smoother", "collision_monitor",
                   "waypoint_follower", "smoother_server"):
        assert "ros__parameters" in nav2[server], server
    assert "ros__parameters" in nav2["local_costmap"]["local_costmap"]
    assert "ros__parameters" in nav2["global_costmap"]["global_costmap"]


def test_nav2_params_hold_the_rosbot_values(nav2):
    for costmap in ("local_costmap", "global_costmap"):
        p = params(nav2, costmap, costmap)
        assert p["robot_radius"] == 0.22
        assert p["resolution"] == 0.05
        assert p["obstacle_layer"]["scan"]["topic"] == "/scan_filtered"
    controller = params(nav2, "controller_server")
    checker = controller[controller["goal_checker_plugins"][0]]
    assert (checker["xy_goal_tolerance"], checker["yaw_goal_tolerance"]) == (0.25, 0.25)
    follow = controller[controller["controller_plugins"][0]]
    assert follow["plugin"] == "nav2_mppi_controller::MPPIController"
    assert follow["motion_model"] == "DiffDrive"
    for server in ("controller_server", "velocity_smoother", "collision_monitor",
                   "behavior_server"):
        assert params(nav2, server)["enable_stamped_cmd_vel"] is True, server
    for server in ("bt_navigator", "velocity_smoother", "controller_server"):
        assert params(nav2, server)["odom_topic"] == "/odometry/filtered", server
    assert params(nav2, "amcl")["scan_topic"] == "scan_filtered"
    assert params(nav2, "amcl")["set_initial_pose"] is False  # the runner seeds AMCL
    assert params(nav2, "collision_monitor")["scan"]["topic"] == "/scan_filtered"
    planner = params(nav2, "planner_server")
    grid = planner[planner["planner_plugins"][0]]
    assert grid["plugin"] == "nav2_navfn_planner::NavfnPlanner"
    assert grid["allow_unknown"] is True
