"""The real-robot launch file and Nav2 parameters, checked without ROS launch installed.

`launch`/`launch_ros` cannot be installed here, so: the file compiles; its declared
arguments (read from the AST) are the README's; run against small stand-ins for the launch
API it starts the expected processes; and config/nav2_params.yaml holds the ROSbot values.
"""

from __future__ import annotations

import ast
import importlib.util
import py_compile
import re
import sys
import types
from pathlib import Path

import pytest
import yaml

from sar_framework.mission.params_file import check_params_file

REPO = Path(__file__).resolve().parents[2]
LAUNCH = REPO / "launch" / "search_and_rescue.launch.py"
NAV2 = REPO / "config" / "nav2_params.yaml"
README = REPO / "README.md"


def declared_arguments() -> dict[str, str]:
    found = {}
    for node in ast.walk(ast.parse(LAUNCH.read_text())):
        if isinstance(node, ast.Call) and getattr(node.func, "id", "") == "DeclareLaunchArgument":
            name = ast.literal_eval(node.args[0])
            defaults = [k.value for k in node.keywords if k.arg == "default_value"]
            found[name] = ast.literal_eval(defaults[0]) if defaults else None
    return found


def readme_arguments() -> dict[str, str]:
    text = README.read_text()
    section = text[text.index("### Real robot launch"):]
    rows = re.findall(r"^\| `(\w+)` \| (.+?) \| .+ \|$", section, flags=re.M)
    return {name: ("" if default == "(empty)" else default.strip("`")) for name, default in rows}


def test_launch_file_compiles(tmp_path):
    py_compile.compile(str(LAUNCH), cfile=str(tmp_path / "launch.pyc"), doraise=True)


def test_declared_arguments_match_the_readme():
    declared = declared_arguments()
    issue_arguments = {"tree", "params_file", "tick_rate_hz", "map", "nav2_params_file",
                       "use_sim_time", "rviz"}
    assert set(declared) == issue_arguments | {"survivors_file", "report_file"}
    assert declared == readme_arguments()
    assert declared["use_sim_time"] == "true" and declared["rviz"] == "false"
    for key in ("tree", "params_file", "map", "nav2_params_file", "survivors_file"):
        assert (REPO / declared[key]).is_file(), declared[key]


# --- run generate_launch_description() against stand-ins ----------------------------------

class Recorded:
    """Any launch class: remembers its arguments."""

    def __init__(self, *args, **kwargs):
        self.args = args
        self.kwargs = kwargs


class LaunchConfiguration(Recorded):
    def perform(self, context):
        return context[self.args[0]]


@pytest.fixture
def launch_module(monkeypatch):
    names = {
        "launch": ["LaunchDescription"],
        "launch.actions": ["DeclareLaunchArgument", "IncludeLaunchDescription",
                           "OpaqueFunction"],
        "launch.conditions": ["IfCondition"],
        "launch.launch_description_sources": ["PythonLaunchDescriptionSource"],
        "launch.substitutions": ["PathJoinSubstitution"],
        "launch_ros": [],
        "launch_ros.actions": ["Node"],
        "launch_ros.substitutions": ["FindPackageShare"],
    }
    for module_name, classes in names.items():
        module = types.ModuleType(module_name)
        for cls in classes:
            setattr(module, cls, type(cls, (Recorded,), {}))
        monkeypatch.setitem(sys.modules, module_name, module)
    sys.modules["launch.substitutions"].LaunchConfiguration = LaunchConfiguration
    spec = importlib.util.spec_from_file_location("sar_launch_under_test", LAUNCH)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def run_setup(module, **overrides):
    description = module.generate_launch_description()
    actions = description.args[0]
    context = {a.args[0]: a.kwargs["default_value"] for a in actions
               if type(a).__name__ == "DeclareLaunchArgument"}
    context.update(overrides)
    (opaque,) = [a for a in actions if type(a).__name__ == "OpaqueFunction"]
    return opaque.kwargs["function"](context)


def test_launch_starts_nav2_the_runner_and_both_servers(launch_module):
    nav2, detect, report, runner, rviz = run_setup(launch_module)
    source = nav2.args[0]
    path_parts = source.args[0].args[0]
    assert path_parts[1:] == ["launch", "bringup_launch.py"]
    nav2_args = dict(nav2.kwargs["launch_arguments"])
    assert nav2_args["map"] == str(REPO / "maps" / "final_project_map.yaml")
    assert nav2_args["params_file"] == str(REPO / "config" / "nav2_params.yaml")
    assert (nav2_args["use_sim_time"], nav2_args["autostart"]) == ("True", "true")

    pyproject = (REPO / "pyproject.toml").read_text()
    scripts = re.findall(r"^([\w-]+) = \"[\w.]+:main\"$", pyproject, flags=re.M)
    for node in (runner, detect, report):
        assert node.kwargs["executable"] in scripts
        assert "package" not in node.kwargs
        assert node.kwargs["output"] == "screen" and node.kwargs["emulate_tty"] is True
    mission_file, runner_params = runner.kwargs["parameters"]
    assert mission_file == str(REPO / "config" / "mission_params.yaml")
    assert runner_params["tree"] == str(REPO / "trees" / "search_and_rescue.yaml")
    assert runner_params["use_sim_time"] is True and runner_params["seed_amcl"] is True
    assert "tick_rate_hz" not in runner_params  # empty argument: keep the file's rate
    assert rviz.kwargs["executable"] == "rviz2"


def test_launch_arguments_are_honoured(launch_module, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "mine.yaml").write_text("format: 1\n")
    _nav2, detect, _report, runner, _rviz = run_setup(
        launch_module, tree="mine.yaml", tick_rate_hz="5", use_sim_time="false")
    runner_params = runner.kwargs["parameters"][1]
    assert runner_params["tree"] == str(tmp_path / "mine.yaml")  # the cwd's file wins
    assert runner_params["tick_rate_hz"] == 5.0
    assert runner_params["use_sim_time"] is False
    assert detect.kwargs["parameters"][0]["use_sim_time"] is False


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
