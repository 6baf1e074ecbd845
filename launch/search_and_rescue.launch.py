"""Real robot (or Gazebo) launch: Nav2 + the mission runner + both service servers.

    ros2 launch launch/search_and_rescue.launch.py [tree:=...] [params_file:=...]
        [tick_rate_hz:=...] [map:=...] [nav2_params_file:=...] [use_sim_time:=true|false]
        [rviz:=true|false]

Relative paths are taken from the working directory when they exist there, else from
this repository (so the defaults work from anywhere). Needs a ROS 2 Jazzy install with
nav2_bringup, and this project pip-installed into the Python that ``ros2 launch`` uses
(see README, "Real robot launch"). Not tested here: no ROS distro can be installed on
our machines; a test checks that this file compiles and that its arguments match the
README.
"""

from __future__ import annotations

from pathlib import Path

from launch.actions import DeclareLaunchArgument, IncludeLaunchDescription, OpaqueFunction
from launch.conditions import IfCondition
from launch.launch_description_sources import PythonLaunchDescriptionSource
from launch.substitutions import LaunchConfiguration, PathJoinSubstitution
from launch_ros.actions import Node
from launch_ros.substitutions import FindPackageShare

from launch import LaunchDescription

REPO = Path(__file__).resolve().parent.parent

# Why launch_ros Node and not ExecuteProcess: this package is pip-installed, not an ament
# package, so there is no `package` to name. launch_ros' Node accepts an executable without
# a package and then runs it by name from PATH, which is where pip puts the console
# scripts (sar-mission-runner, ...). Node still gives us ROS-aware handling: parameter
# dicts and files become --params-file arguments, the node name is set, and SIGINT on
# shutdown reaches the process (so the runner cancels a Nav2 goal in flight).
RUNNER = "sar-mission-runner"
DETECT_SERVER = "sar-detect-survivor-server"
REPORT_SERVER = "sar-report-survivor-server"

ARGUMENTS = [
    DeclareLaunchArgument("tree", default_value="trees/search_and_rescue.yaml",
                          description="Behaviour tree file the runner loads."),
    DeclareLaunchArgument("params_file", default_value="config/mission_params.yaml",
                          description="Mission parameters (zones, base station, tick rate)."),
    DeclareLaunchArgument("survivors_file", default_value="config/survivors.yaml",
                          description="Survivor table the detect server answers from."),
    DeclareLaunchArgument("report_file", default_value="~/.ros/sar_reports.jsonl",
                          description="JSON Lines file of acknowledged survivor reports."),
    DeclareLaunchArgument("tick_rate_hz", default_value="",
                          description="Override the tick rate of params_file (empty: keep)."),
    DeclareLaunchArgument("map", default_value="maps/final_project_map.yaml",
                          description="map_server map file for Nav2."),
    DeclareLaunchArgument("nav2_params_file", default_value="config/nav2_params.yaml",
                          description="Nav2 parameters (ROSbot)."),
    DeclareLaunchArgument("use_sim_time", default_value="true",
                          description="Follow /clock (Gazebo); false on the real robot."),
    DeclareLaunchArgument("rviz", default_value="false",
                          description="Start RViz with Nav2's default view."),
]


def _path(text: str) -> str:
    """Resolve a launch argument path: as given if it exists, else under the repository."""
    given = Path(text).expanduser()
    if given.is_absolute() or given.exists():
        return str(given.resolve())
    return str(REPO / given)


def _launch_setup(context: object) -> list:
    """Build the actions once the arguments are known (paths resolved, empty ones skipped)."""
    def arg(name: str) -> str:
        return LaunchConfiguration(name).perform(context)

    use_sim_time = arg("use_sim_time").lower() in ("true", "1", "yes")
    params_file = _path(arg("params_file"))

    nav2 = IncludeLaunchDescription(
        PythonLaunchDescriptionSource(
            PathJoinSubstitution([FindPackageShare("nav2_bringup"), "launch",
                                  "bringup_launch.py"])),
        launch_arguments={
            "map": _path(arg("map")),
            "params_file": _path(arg("nav2_params_file")),
            "use_sim_time": str(use_sim_time),
            "autostart": "true",
        }.items(),
    )

    runner_params: dict[str, object] = {
        "tree": _path(arg("tree")),
        "use_sim_time": use_sim_time,
        "seed_amcl": True,
        "nav2_timeout_s": 90.0,  # Nav2 bring-up next to Gazebo can take a while
    }
    if arg("tick_rate_hz"):
        runner_params["tick_rate_hz"] = float(arg("tick_rate_hz"))
    common = {"output": "screen", "emulate_tty": True}
    runner = Node(executable=RUNNER, name="sar_mission_runner",
                  parameters=[params_file, runner_params], **common)
    detect = Node(executable=DETECT_SERVER, name="detect_survivor_server",
                  parameters=[{"survivors_file": _path(arg("survivors_file")),
                               "use_sim_time": use_sim_time}], **common)
    report = Node(executable=REPORT_SERVER, name="report_survivor_server",
                  parameters=[{"report_file": str(Path(arg("report_file")).expanduser()),
                               "use_sim_time": use_sim_time}], **common)
    rviz = Node(package="rviz2", executable="rviz2", name="rviz2",
                arguments=["-d", PathJoinSubstitution([FindPackageShare("nav2_bringup"), "rviz",
                                                       "nav2_default_view.rviz"])],
                parameters=[{"use_sim_time": use_sim_time}],
                condition=IfCondition(LaunchConfiguration("rviz")), output="screen")
    return [nav2, detect, report, runner, rviz]


def generate_launch_description() -> LaunchDescription:
    """Nav2 bringup, the two servers and the runner, with the arguments above."""
    return LaunchDescription([*ARGUMENTS, OpaqueFunction(function=_launch_setup)])
