"""Upstream Nav2 clients against the simulator: nav2_simple_commander and the ros2 CLI.

Needs the real Jazzy ``nav2_msgs``, ``nav2_simple_commander`` and ``ros2cli`` (built from
``../shared/ros-overlay``); skipped where they are absent. Before, ``lifecycleStartup``
blocked (no lifecycle manager), ``getPath``/``smoothPath``/``spin``/``backup``/
``clearAllCostmaps`` waited forever for servers that did not exist, and
``ros2 lifecycle list /amcl`` hung.
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from sar_testing.processes import NodeProcess
from sar_testing.ros2_cli import ros2_daemon, ros2_executable, run_ros2

pytest.importorskip("nav2_simple_commander.robot_navigator",
                    reason="nav2_simple_commander (real Jazzy overlay) is not installed")
pytestmark = [pytest.mark.ros, pytest.mark.timeout(180)]
MANAGERS = 2  # lifecycle_manager_localization, lifecycle_manager_navigation


def start_sim(log_dir: Path, *params: str) -> NodeProcess:
    args = ["-m", "sar_framework.sim", "--ros-args", "-p", "speed:=20.0"]
    for param in params:
        args += ["-p", param]
    proc = NodeProcess(args, "sim", log_dir=log_dir).start()
    proc.wait_for_output("ready", timeout=30)
    return proc


@pytest.fixture
def navigator(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Any]:
    """A BasicNavigator next to a simulator started as Nav2 with ``autostart:=false``."""
    import rclpy
    from nav2_simple_commander.robot_navigator import BasicNavigator

    sim = start_sim(tmp_path_factory.mktemp("sim"), "autostart:=false", "auto_localize:=false")
    context_owner = not rclpy.ok()
    if context_owner:
        rclpy.init()
    nav = BasicNavigator()
    try:
        deadline = time.monotonic() + 60.0  # outer safety bound (discovery: a second or two)
        while time.monotonic() < deadline and sum(  # outer safety bound
            types == ["nav2_msgs/srv/ManageLifecycleNodes"]
            for _name, types in nav.get_service_names_and_types()
        ) < MANAGERS:  # lifecycleStartup only calls the managers it has discovered
            rclpy.spin_once(nav, timeout_sec=0.1)
        yield nav
    finally:
        nav.destroy_node()
        if context_owner:
            rclpy.shutdown()
        sim.stop()


def pose(nav: Any, x: float, y: float, yaw: float = 0.0) -> Any:
    from geometry_msgs.msg import PoseStamped

    msg = PoseStamped()
    msg.header.frame_id = "map"
    msg.header.stamp = nav.get_clock().now().to_msg()
    msg.pose.position.x, msg.pose.position.y = x, y
    msg.pose.orientation.z, msg.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    return msg


def task(nav: Any, started: bool) -> tuple[Any, list[Any], Any]:
    """Wait for the task; return (TaskResult, every new feedback seen, the raw result)."""
    assert started, "the goal was rejected"
    return finish(nav)


def send(nav: Any, method: str, *args: Any, **kwargs: Any) -> tuple[Any, list[Any], Any]:
    """Call a BasicNavigator task method and wait for the task (see :func:`finish`)."""
    nav.feedback = None  # BasicNavigator keeps the last task's feedback otherwise
    return task(nav, getattr(nav, method)(*args, **kwargs))


def seconds(duration: Any) -> float:
    return duration.sec + duration.nanosec * 1e-9


def finish(nav: Any) -> tuple[Any, list[Any], Any]:
    """Wait for the task; return (TaskResult, every feedback seen, the raw result)."""
    feedback = []
    while not nav.isTaskComplete():
        if nav.getFeedback() is not None and (not feedback or feedback[-1] is not
                                              nav.getFeedback()):
            feedback.append(nav.getFeedback())
    return nav.getResult(), feedback, nav.result_future.result().result


def set_sim_speed(nav: Any, speed: float) -> None:
    """Set the simulator's ``speed`` through its parameter service, as ``ros2 param set`` does."""
    import rclpy
    from rcl_interfaces.srv import SetParameters
    from rclpy.parameter import Parameter

    client = nav.create_client(SetParameters, "/sar_sim/set_parameters")
    assert client.wait_for_service(timeout_sec=30.0), "no /sar_sim/set_parameters service"
    request = SetParameters.Request(parameters=[Parameter("speed", value=speed).to_parameter_msg()])
    future = client.call_async(request)
    rclpy.spin_until_future_complete(nav, future, timeout_sec=30.0)  # outer safety bound
    assert future.done() and future.result().results[0].successful, "speed not set"
    nav.destroy_client(client)


def test_basic_navigator_whole_api(navigator: Any) -> None:
    from nav2_simple_commander.robot_navigator import TaskResult

    nav = navigator
    nav.setInitialPose(pose(nav, 0.0, 0.0))
    nav.lifecycleStartup()
    nav.waitUntilNav2Active()
    assert nav.initial_pose_received

    path = nav.getPath(pose(nav, 0.0, 0.0), pose(nav, 1.0, 0.5, 1.0))
    assert path is not None and len(path.poses) > 10 and path.header.frame_id == "map"
    end = path.poses[-1].pose
    assert (end.position.x, end.position.y) == pytest.approx((1.0, 0.5), abs=0.06)
    smoothed = nav.smoothPath(path)
    assert len(smoothed.poses) == len(path.poses)
    assert smoothed.poses[-1].pose.position.x == pytest.approx(end.position.x)

    result, feedback, _ = send(nav, "goToPose", pose(nav, 1.0, 0.5))
    assert result == TaskResult.SUCCEEDED
    # Feedback is best-effort in count (BasicNavigator keeps the latest; a loaded client may
    # see one): what is seen must never move away from the goal.
    distances = [f.distance_remaining for f in feedback]
    assert distances and distances[-1] <= distances[0], distances

    result, feedback, _ = send(nav, "goThroughPoses",
                               [pose(nav, 1.0, -0.5), pose(nav, 0.0, 0.0)])
    assert result == TaskResult.SUCCEEDED
    left = [f.number_of_poses_remaining for f in feedback]
    assert left and left == sorted(left, reverse=True) and set(left) <= {2, 1, 0}, left

    result, feedback, raw = send(nav, "followWaypoints",
                                 [pose(nav, 0.5, 0.0), pose(nav, 0.0, 0.0)])
    assert result == TaskResult.SUCCEEDED and list(raw.missed_waypoints) == []
    # At 20x the first leg lasts ~50 ms of wall time: a loaded client may spin past its
    # feedback. What is seen must count up to the last waypoint.
    seen = [f.current_waypoint for f in feedback]
    assert seen and seen == sorted(seen) and set(seen) <= {0, 1} and seen[-1] == 1, seen

    result, feedback, raw = send(nav, "spin", spin_dist=3.0)
    assert result == TaskResult.SUCCEEDED and raw.error_code == 0
    assert seconds(raw.total_elapsed_time) == pytest.approx(3.0, abs=0.2)  # at 1 rad/s
    assert all(0.0 <= f.angular_distance_traveled <= 3.0 for f in feedback)

    result, feedback, raw = send(nav, "backup", backup_dist=0.15, backup_speed=0.05)
    assert result == TaskResult.SUCCEEDED, raw.error_msg
    assert seconds(raw.total_elapsed_time) == pytest.approx(3.0, abs=0.2)  # 0.15 m, 0.05 m/s
    assert all(0.0 <= f.distance_traveled <= 0.15 for f in feedback)

    nav.clearAllCostmaps()  # returns only once both services answered

    # At 20x the drive is over in well under a second of wall time, so a loaded machine could
    # deliver the cancel after it ended: drive at 1x, and cancel once the goal is running.
    set_sim_speed(nav, 1.0)
    nav.feedback = None
    assert nav.goToPose(pose(nav, 4.0, -3.0))
    deadline = time.monotonic() + 60.0  # outer safety bound (the first feedback: milliseconds)
    while nav.getFeedback() is None and not nav.isTaskComplete():
        waited = time.monotonic() < deadline  # outer safety bound
        assert waited, "no feedback from the goal to cancel"
    nav.cancelTask()
    result, _, _ = finish(nav)
    assert result == TaskResult.CANCELED

    nav.lifecycleShutdown()
    assert not nav.goToPose(pose(nav, 1.0, 0.5))  # bt_navigator is finalized: rejected


# ---------------------------------------------------------------------------- ros2 CLI


def ros2(*args: str, expect: str = "") -> str:
    if ros2_executable() is None:
        pytest.skip("the ros2 command line is not installed here")
    return run_ros2(*args, expect=expect, daemon=True)


@pytest.fixture(scope="class")
def active_sim(tmp_path_factory: pytest.TempPathFactory) -> Iterator[NodeProcess]:
    """An autostarted simulator (the BasicNavigator test's one is gone by then), and the
    ``ros2`` daemon (the command line's default) discovering it meanwhile."""
    if ros2_executable() is None:
        pytest.skip("the ros2 command line is not installed here")
    with ros2_daemon():
        proc = start_sim(tmp_path_factory.mktemp("sim_cli"))
        yield proc
        proc.stop()


@pytest.mark.usefixtures("active_sim")
class TestRos2Cli:
    def test_lifecycle_list_and_set(self) -> None:
        listed = ros2("lifecycle", "list", "/amcl", expect="deactivate [4]")
        assert "shutdown [7]" in listed
        ros2("lifecycle", "get", "/bt_navigator", expect="active [3]")
        ros2("lifecycle", "set", "/bt_navigator", "deactivate",
             expect="Transitioning successful")
        ros2("lifecycle", "get", "/bt_navigator", expect="inactive [2]")
        ros2("lifecycle", "set", "/bt_navigator", "activate", expect="Transitioning successful")

    def test_topic_echo_amcl_pose(self) -> None:
        echoed = ros2("topic", "echo", "/amcl_pose", "--once", expect="frame_id: map")
        assert "covariance:" in echoed

    def test_node_list_is_a_nav2_bringup(self) -> None:
        nodes = set(ros2("node", "list", expect="/lifecycle_manager_navigation").split())
        assert {"/map_server", "/amcl", "/planner_server", "/controller_server",
                "/smoother_server", "/behavior_server", "/bt_navigator", "/waypoint_follower",
                "/lifecycle_manager_localization", "/lifecycle_manager_navigation",
                "/global_costmap/global_costmap", "/local_costmap/local_costmap"} <= nodes
