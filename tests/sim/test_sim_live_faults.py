"""Run-time fault parameters and ``/sar_sim/reset`` over real DDS (DESIGN21's contract).

One simulator (40x) and one client node for the module; each test leaves the faults unset.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

import pytest
from sar_testing.processes import NodeProcess
from sar_testing.spin import ros_node, spin_until

from sar_framework.testing.sim_control import odometry_xy, reset_sim, set_sim_params, sim_process

pytestmark = [pytest.mark.ros, pytest.mark.timeout(180)]
pytest.importorskip("nav2_msgs.action", reason="needs the full nav2_msgs")
DISCOVERY_S = 15.0


@pytest.fixture(scope="module")
def sim(tmp_path_factory: pytest.TempPathFactory) -> Iterator[NodeProcess]:
    with sim_process(tmp_path_factory.mktemp("sim"), speed=40.0) as proc:
        yield proc


@pytest.fixture(scope="module")
def client(sim: NodeProcess) -> Iterator[tuple[Any, Any]]:
    with ros_node("sim_live_faults_test") as pair:
        yield pair


@pytest.fixture
def clean(client: tuple[Any, Any]) -> Iterator[tuple[Any, Any]]:
    """Faults unset and the world reset after the test."""
    yield client
    set_sim_params(*client, phantom_obstacles=[""], stuck_recoveries=0,
                   movement_time_allowance=10.0, blocked_areas=[""])
    assert reset_sim(*client).success


def compute_path(client: tuple[Any, Any], x: float, y: float) -> Any:
    """ComputePathToPose from the robot to ``(x, y)``; the result."""
    from nav2_msgs.action import ComputePathToPose

    goal = ComputePathToPose.Goal(goal=map_pose(x, y))
    return run_action(client, ComputePathToPose, "compute_path_to_pose", goal)


def run_action(client: tuple[Any, Any], kind: Any, name: str, goal: Any,
               timeout: float = 30.0) -> Any:
    """Send ``goal``, wait for the result; the ``GetResult`` response (status, result)."""
    from rclpy.action import ActionClient

    node, executor = client
    action = ActionClient(node, kind, name)
    try:
        assert spin_until(executor, action.server_is_ready, DISCOVERY_S)
        sent = action.send_goal_async(goal)
        assert spin_until(executor, sent.done, 10.0)
        handle = sent.result()
        assert handle.accepted
        done = handle.get_result_async()
        assert spin_until(executor, done.done, timeout)
        return done.result()
    finally:
        action.destroy()


@pytest.mark.parametrize(("name", "value", "expect"), [
    ("phantom_obstacles", ["1:2"], "phantom_obstacles: '1:2': expected 'x:y:radius'"),
    ("phantom_obstacles", ["nowhere"], "phantom_obstacles: 'nowhere': expected"),
    ("phantom_obstacles", ["1:x:0.3"], "phantom_obstacles: '1:x:0.3': 'x' is not a number"),
    ("phantom_obstacles", ["1:1:-0.3"], "radius must be positive"),
    ("stuck_recoveries", -1, "stuck_recoveries out of range. Min: 0"),
    ("movement_time_allowance", 0.0, "movement_time_allowance: must be > 0"),
    ("map_yaml", "other.yaml", "map_yaml cannot change at run time"),
])
def test_a_bad_value_is_refused_naming_the_parameter(
        clean: tuple[Any, Any], sim: NodeProcess, name: str, value: Any, expect: str) -> None:
    (result,) = set_sim_params(*clean, **{name: value})
    assert not result.successful
    assert expect in result.reason
    assert sim.returncode() is None  # still running, still answering
    (again,) = set_sim_params(*clean, phantom_obstacles=["3.5:3.0:0.4"])
    assert again.successful


def test_a_phantom_at_the_goal_fails_planning_until_it_is_unset(
        clean: tuple[Any, Any]) -> None:
    assert compute_path(clean, 1.0, -0.5).result.error_code == 0
    assert set_sim_params(*clean, phantom_obstacles=["1.0:-0.5:0.3"])[0].successful
    answer = compute_path(clean, 1.0, -0.5)
    assert answer.result.error_code == 206  # GOAL_OCCUPIED
    assert set_sim_params(*clean, phantom_obstacles=[""])[0].successful
    assert compute_path(clean, 1.0, -0.5).result.error_code == 0


def test_blocked_areas_set_at_run_time_are_walls_until_unset(clean: tuple[Any, Any]) -> None:
    from nav2_msgs.srv import ClearEntireCostmap
    from sar_testing.spin import call_service

    assert set_sim_params(*clean, blocked_areas=["1.0:-0.5:0.3"])[0].successful
    assert compute_path(clean, 1.0, -0.5).result.error_code == 206
    call_service(*clean, ClearEntireCostmap, "/global_costmap/clear_entirely_global_costmap",
                 ClearEntireCostmap.Request())
    assert compute_path(clean, 1.0, -0.5).result.error_code == 206  # a wall stays
    assert set_sim_params(*clean, blocked_areas=[""])[0].successful
    assert compute_path(clean, 1.0, -0.5).result.error_code == 0


def map_pose(x: float, y: float) -> Any:
    from sar_framework.sim.messages import pose_stamped
    from sar_framework.sim.world import Pose2D

    return pose_stamped(Pose2D(x, y, 0.0), "map", 0)


def reset_mid_goal(clean: tuple[Any, Any], kind: Any, name: str, goal: Any) -> tuple[Any, Any]:
    """Send ``goal``, reset once the robot has moved 0.3 m; (reset answer, goal status)."""
    from rclpy.action import ActionClient

    node, executor = clean
    action = ActionClient(node, kind, name)
    try:
        assert spin_until(executor, action.server_is_ready, DISCOVERY_S)
        sent = action.send_goal_async(goal)
        assert spin_until(executor, sent.done, 10.0) and sent.result().accepted
        assert spin_until(executor, lambda: math.hypot(*odometry_xy(*clean)) > 0.3, 30.0)
        done = sent.result().get_result_async()
        answer = reset_sim(*clean)
        assert spin_until(executor, done.done, 10.0)
        return answer, done.result().status
    finally:
        action.destroy()


def test_reset_aborts_the_running_goal_and_puts_the_robot_at_spawn(
        clean: tuple[Any, Any]) -> None:
    from action_msgs.msg import GoalStatus
    from geometry_msgs.msg import PoseWithCovarianceStamped
    from nav2_msgs.action import NavigateToPose
    from rclpy.qos import DurabilityPolicy, QoSProfile

    node, executor = clean
    goal = NavigateToPose.Goal(pose=map_pose(-3.0, 3.0))  # zone_a: far
    answer, status = reset_mid_goal(clean, NavigateToPose, "navigate_to_pose", goal)
    assert answer.success, answer.message
    assert "goal" in answer.message and "aborted" in answer.message
    assert status == GoalStatus.STATUS_ABORTED
    assert math.hypot(*odometry_xy(*clean)) < 0.01
    seen: list[PoseWithCovarianceStamped] = []
    qos = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    node.create_subscription(PoseWithCovarianceStamped, "/amcl_pose", seen.append, qos)
    assert spin_until(executor, lambda: bool(seen), 10.0)
    p = seen[-1].pose.pose.position
    assert math.hypot(p.x, p.y) < 0.01
    # Goal numbers restart: the next goal runs normally.
    assert compute_path(clean, 1.0, -0.5).result.error_code == 0


def test_reset_ends_follow_waypoints_aborted_not_at_the_next_waypoint(
        clean: tuple[Any, Any]) -> None:
    from action_msgs.msg import GoalStatus
    from nav2_msgs.action import FollowWaypoints

    goal = FollowWaypoints.Goal(poses=[map_pose(-3.0, 3.0), map_pose(1.0, -0.5)])
    answer, status = reset_mid_goal(clean, FollowWaypoints, "follow_waypoints", goal)
    assert answer.success and status == GoalStatus.STATUS_ABORTED
    assert math.hypot(*odometry_xy(*clean)) < 0.01  # not driving to the next waypoint
