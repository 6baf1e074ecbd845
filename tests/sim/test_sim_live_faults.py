"""Run-time fault parameters and ``/sar_sim/reset`` over real DDS (DESIGN21's contract).

One simulator (40x) and one client node for the module; each test leaves the faults unset.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

import pytest
from sar_testing.processes import NodeProcess
from sar_testing.spin import call_service, ros_node, spin_until

pytestmark = [pytest.mark.ros, pytest.mark.timeout(180)]
pytest.importorskip("nav2_msgs.action", reason="needs the full nav2_msgs")
DISCOVERY_S = 15.0
SPEED = 40.0


@pytest.fixture(scope="module")
def sim(tmp_path_factory: pytest.TempPathFactory) -> Iterator[NodeProcess]:
    args = ["-m", "sar_framework.sim", "--ros-args", "-p", f"speed:={SPEED}"]
    with NodeProcess(args, "sim", log_dir=tmp_path_factory.mktemp("sim")) as proc:
        proc.wait_for_output("ready", timeout=30)
        yield proc


@pytest.fixture(scope="module")
def client(sim: NodeProcess) -> Iterator[tuple[Any, Any]]:
    with ros_node("sim_live_faults_test") as pair:
        yield pair


@pytest.fixture
def clean(client: tuple[Any, Any]) -> Iterator[tuple[Any, Any]]:
    """Faults unset and the world reset after the test."""
    yield client
    set_params(client, phantom_obstacles=[""], stuck_recoveries=0,
               movement_time_allowance=10.0)
    assert reset(client).success


def set_params(client: tuple[Any, Any], **values: Any) -> list[Any]:
    """SetParameters on /sar_sim, as ``ros2 param set`` does; returns the results."""
    from rcl_interfaces.srv import SetParameters
    from rclpy.parameter import Parameter

    request = SetParameters.Request()
    request.parameters = [Parameter(name, value=value).to_parameter_msg()
                          for name, value in values.items()]
    answer = call_service(*client, SetParameters, "/sar_sim/set_parameters", request)
    return list(answer.results)


def reset(client: tuple[Any, Any]) -> Any:
    from std_srvs.srv import Trigger

    return call_service(*client, Trigger, "/sar_sim/reset", Trigger.Request(), timeout=20.0)


def compute_path(client: tuple[Any, Any], x: float, y: float) -> Any:
    """ComputePathToPose from the robot to ``(x, y)``; the result."""
    from nav2_msgs.action import ComputePathToPose

    goal = ComputePathToPose.Goal()
    goal.goal.header.frame_id = "map"
    goal.goal.pose.position.x, goal.goal.pose.position.y = x, y
    goal.goal.pose.orientation.w = 1.0
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


def odom_pose(client: tuple[Any, Any]) -> tuple[float, float]:
    from nav_msgs.msg import Odometry

    node, executor = client
    seen: list[Odometry] = []
    sub = node.create_subscription(Odometry, "/odometry/filtered", seen.append, 10)
    try:
        assert spin_until(executor, lambda: len(seen) >= 2, 10.0)
        p = seen[-1].pose.pose.position
        return p.x, p.y
    finally:
        node.destroy_subscription(sub)


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
    (result,) = set_params(clean, **{name: value})
    assert not result.successful
    assert expect in result.reason
    assert sim.returncode() is None  # still running, still answering
    assert [r.successful for r in set_params(clean, phantom_obstacles=["zone_b:0.4"])] == [True]


def test_a_phantom_at_the_goal_fails_planning_until_it_is_unset(
        clean: tuple[Any, Any]) -> None:
    assert compute_path(clean, 1.0, -0.5).result.error_code == 0
    assert set_params(clean, phantom_obstacles=["1.0:-0.5:0.3"])[0].successful
    answer = compute_path(clean, 1.0, -0.5)
    assert answer.result.error_code == 206  # GOAL_OCCUPIED
    assert set_params(clean, phantom_obstacles=[""])[0].successful
    assert compute_path(clean, 1.0, -0.5).result.error_code == 0


def test_reset_aborts_the_running_goal_and_puts_the_robot_at_spawn(
        clean: tuple[Any, Any]) -> None:
    from action_msgs.msg import GoalStatus
    from geometry_msgs.msg import PoseWithCovarianceStamped
    from nav2_msgs.action import NavigateToPose
    from rclpy.action import ActionClient
    from rclpy.qos import DurabilityPolicy, QoSProfile

    node, executor = clean
    action = ActionClient(node, NavigateToPose, "navigate_to_pose")
    assert spin_until(executor, action.server_is_ready, DISCOVERY_S)
    goal = NavigateToPose.Goal()
    goal.pose.header.frame_id = "map"
    goal.pose.pose.position.x, goal.pose.pose.position.y = -3.0, 3.0  # zone_a: far
    goal.pose.pose.orientation.w = 1.0
    sent = action.send_goal_async(goal)
    assert spin_until(executor, sent.done, 10.0) and sent.result().accepted
    assert spin_until(executor, lambda: math.hypot(*odom_pose(clean)) > 0.3, 30.0)
    done = sent.result().get_result_async()

    answer = reset(clean)
    assert answer.success, answer.message
    assert "goal" in answer.message and "aborted" in answer.message
    assert spin_until(executor, done.done, 10.0)
    assert done.result().status == GoalStatus.STATUS_ABORTED
    assert math.hypot(*odom_pose(clean)) < 0.01
    seen: list[PoseWithCovarianceStamped] = []
    qos = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    node.create_subscription(PoseWithCovarianceStamped, "/amcl_pose", seen.append, qos)
    assert spin_until(executor, lambda: bool(seen), 10.0)
    p = seen[-1].pose.pose.position
    assert math.hypot(p.x, p.y) < 0.01
    action.destroy()
    # Goal numbers restart: the next goal runs normally.
    assert compute_path(clean, 1.0, -0.5).result.error_code == 0
