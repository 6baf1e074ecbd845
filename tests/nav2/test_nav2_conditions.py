"""Nav2's ROS-free conditions and path tools, built from tree files, ticked without a simulator.

Times come from a fake clock; the robot's pose for GoalReached is given; Nav2's error codes
are read from the real ``nav2_msgs`` (built in the venv).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import pytest
from py_trees.blackboard import Blackboard
from py_trees.common import Status

from sar_framework.engine.api import load_tree

pytest.importorskip("nav2_msgs.action", reason="needs the full nav2_msgs")
from geometry_msgs.msg import PoseStamped
from nav2_msgs.action import ComputePathThroughPoses, ComputePathToPose, FollowPath
from nav_msgs.msg import Odometry
from nav_msgs.msg import Path as PathMsg
from sar_plugins.nav2.conditions import Deceleration
from sar_plugins.nav2.path_tools import remove_passed, truncate


@pytest.fixture(autouse=True)
def clean_blackboard() -> None:
    Blackboard.storage.clear()


def pose(x: float, y: float) -> PoseStamped:
    msg = PoseStamped()
    msg.header.frame_id = "map"
    msg.pose.position.x, msg.pose.position.y = x, y
    msg.pose.orientation.w = 1.0
    return msg


def leaf_of(tmp_path: Path, body: str, blackboard: str = "") -> Any:
    tree = tmp_path / "t.yaml"
    tree.write_text(f"format: 1\n{blackboard}root:\n  {body}\n")
    return load_tree(tree, {}).root


def tick(behaviour: Any) -> Status:
    behaviour.tick_once()
    return behaviour.status


CONTROLLER_HELPS = [FollowPath.Result.UNKNOWN, FollowPath.Result.PATIENCE_EXCEEDED,
                    FollowPath.Result.FAILED_TO_MAKE_PROGRESS,
                    FollowPath.Result.NO_VALID_CONTROL]
PLANNER_HELPS = [ComputePathToPose.Result.UNKNOWN, ComputePathToPose.Result.NO_VALID_PATH,
                 ComputePathToPose.Result.TIMEOUT, ComputePathThroughPoses.Result.NO_VALID_PATH]


@pytest.mark.parametrize(("kind", "code", "expected"), [
    *[("WouldAControllerRecoveryHelp", c, Status.SUCCESS) for c in CONTROLLER_HELPS],
    ("WouldAControllerRecoveryHelp", FollowPath.Result.INVALID_CONTROLLER, Status.FAILURE),
    ("WouldAControllerRecoveryHelp", FollowPath.Result.NONE, Status.FAILURE),
    ("WouldAControllerRecoveryHelp", ComputePathToPose.Result.NO_VALID_PATH, Status.FAILURE),
    *[("WouldAPlannerRecoveryHelp", c, Status.SUCCESS) for c in PLANNER_HELPS],
    ("WouldAPlannerRecoveryHelp", ComputePathToPose.Result.GOAL_OCCUPIED, Status.FAILURE),
    ("WouldAPlannerRecoveryHelp", FollowPath.Result.PATIENCE_EXCEEDED, Status.FAILURE),
])
def test_would_a_recovery_help_reads_nav2_error_codes(tmp_path: Path, kind: str, code: int,
                                                      expected: Status) -> None:
    root = leaf_of(tmp_path, f'{kind}: {{error_code: "{{code}}"}}',
                   f"blackboard:\n  code: {{type: int, initial: {code}}}\n")
    assert tick(root) == expected
    assert (code, expected) != (0, Status.SUCCESS)


def test_would_a_recovery_help_fails_without_an_error_code(tmp_path: Path) -> None:
    root = leaf_of(tmp_path, 'WouldAPlannerRecoveryHelp: {error_code: "{code}"}',
                   "blackboard:\n  code: {type: int}\n")
    assert tick(root) == Status.FAILURE


class FakeClock:
    def __init__(self) -> None:
        self.t = 100.0

    def __call__(self) -> float:
        return self.t


def test_time_expired_fires_every_period_of_an_active_run(tmp_path: Path) -> None:
    root = leaf_of(tmp_path, "TimeExpired: {seconds: 2.0}")
    clock = FakeClock()
    root.now = clock
    assert tick(root) == Status.FAILURE  # first tick: the timer starts
    clock.t += 1.9
    assert tick(root) == Status.FAILURE
    clock.t += 0.2
    assert tick(root) == Status.SUCCESS  # and the timer restarts
    clock.t += 1.0
    assert tick(root) == Status.FAILURE
    root.stop(Status.INVALID)  # the parent resets it: a new active period
    clock.t += 5.0
    assert tick(root) == Status.FAILURE
    clock.t += 2.0
    assert tick(root) == Status.SUCCESS


def test_path_expiring_timer_restarts_on_a_new_path(tmp_path: Path) -> None:
    root = leaf_of(tmp_path, 'PathExpiringTimer: {seconds: 1.0, path: "{path}"}',
                   "blackboard:\n  path: {type: nav_msgs/msg/Path}\n")
    clock = FakeClock()
    root.now = clock
    first = PathMsg(poses=[pose(0.0, 0.0)])
    Blackboard.storage["/path"] = first
    assert tick(root) == Status.FAILURE
    clock.t += 0.8
    Blackboard.storage["/path"] = PathMsg(poses=[pose(1.0, 0.0)])  # a new path
    assert tick(root) == Status.FAILURE
    clock.t += 0.8  # 1.6 s from the start, 0.8 s from the new path
    assert tick(root) == Status.FAILURE
    clock.t += 0.3
    assert tick(root) == Status.SUCCESS
    Blackboard.storage["/path"] = PathMsg(poses=[pose(1.0, 0.0)])  # equal: not new
    clock.t += 1.0
    assert tick(root) == Status.SUCCESS


def test_goal_updated_compares_with_the_goal_of_its_active_period(tmp_path: Path) -> None:
    root = leaf_of(tmp_path, "GoalUpdated: {}",
                   "blackboard:\n  goal: {type: geometry_msgs/msg/PoseStamped}\n")
    Blackboard.storage["/goal"] = pose(1.0, 1.0)  # unbound ports: the root's {goal}
    assert tick(root) == Status.FAILURE
    assert tick(root) == Status.FAILURE
    Blackboard.storage["/goal"] = pose(2.0, 1.0)
    assert tick(root) == Status.SUCCESS
    assert tick(root) == Status.FAILURE
    Blackboard.storage["/goal"] = pose(3.0, 1.0)
    root.stop(Status.INVALID)  # reset: the next tick only notes the goal
    assert tick(root) == Status.FAILURE


def test_goal_updated_reset_by_a_btcpp_parent_starts_a_new_active_period(
        tmp_path: Path) -> None:
    root = leaf_of(tmp_path, "Sequence: {children: [GoalUpdated: {}]}",
                   "blackboard:\n  goal: {type: geometry_msgs/msg/PoseStamped}\n")
    condition = root.children[0]
    Blackboard.storage["/goal"] = pose(1.0, 1.0)
    assert tick(root) == Status.FAILURE  # the Sequence fails and resets it to IDLE
    assert condition.status == Status.FAILURE  # py_trees still shows what it returned
    Blackboard.storage["/goal"] = pose(2.0, 1.0)
    assert tick(root) == Status.FAILURE  # not active: the goal is only noted
    Blackboard.storage["/goal"] = pose(3.0, 1.0)
    assert tick(root) == Status.FAILURE


def test_global_updated_goal_remembers_across_resets(tmp_path: Path) -> None:
    root = leaf_of(tmp_path, 'GlobalUpdatedGoal: {goal: "{goal}"}',
                   "blackboard:\n  goal: {type: geometry_msgs/msg/PoseStamped}\n")
    Blackboard.storage["/goal"] = pose(1.0, 1.0)
    assert tick(root) == Status.FAILURE
    Blackboard.storage["/goal"] = pose(3.0, 1.0)
    root.stop(Status.INVALID)
    assert tick(root) == Status.SUCCESS
    assert tick(root) == Status.FAILURE


@pytest.mark.parametrize(("robot", "expected"), [
    ((1.0, 1.0), Status.SUCCESS), ((1.2, 1.1), Status.SUCCESS), ((1.2, 1.2), Status.FAILURE),
    (None, Status.FAILURE),
])
def test_goal_reached_within_nav2s_tolerance(tmp_path: Path, robot: tuple[float, float] | None,
                                             expected: Status) -> None:
    root = leaf_of(tmp_path, 'GoalReached: {goal: "{goal}"}',
                   "blackboard:\n  goal: {type: geometry_msgs/msg/PoseStamped}\n")
    Blackboard.storage["/goal"] = pose(1.0, 1.0)
    root.robot = lambda: None if robot is None else pose(*robot)
    assert tick(root) == expected  # 0.25 m: (0.2, 0.1) is in, (0.2, 0.2) is 0.28 m out


def odometry(t: float, vx: float) -> Odometry:
    msg = Odometry()
    msg.header.stamp.sec, msg.header.stamp.nanosec = int(t), round((t % 1) * 1e9)
    msg.twist.twist.linear.x = vx
    return msg


def test_is_stuck_on_a_harsh_deceleration_only(tmp_path: Path) -> None:
    root = leaf_of(tmp_path, "IsStuck: {}")
    assert tick(root) == Status.FAILURE  # no odometry: free
    for i, vx in enumerate([0.5, 0.5, 0.48, 0.3, 0.1]):  # braking at -4 m/s² at most
        root.on_odometry(odometry(10.0 + 0.05 * i, vx))
    assert tick(root) == Status.FAILURE
    root.on_odometry(odometry(10.3, 0.0))  # 0.1 -> 0.0 in 0.05 s: -2 m/s²
    assert tick(root) == Status.FAILURE
    root.on_odometry(odometry(10.35, 0.5))
    root.on_odometry(odometry(10.37, 0.0))  # -25 m/s²: a bump
    assert tick(root) == Status.SUCCESS
    assert root.feedback_message == "Robot got stuck!"
    root.on_odometry(odometry(10.42, 0.0))
    assert tick(root) == Status.FAILURE


def test_deceleration_needs_three_samples_as_nav2() -> None:
    watch = Deceleration()
    watch.add(1.0, 1.0)
    watch.add(1.01, 0.0)  # only two samples: no acceleration yet
    assert not watch.stuck
    watch.add(1.02, -1.0)
    assert watch.stuck and watch.accel == pytest.approx(-100.0)


def test_remove_passed_goals_keeps_the_last() -> None:
    goals = [pose(0.0, 0.0), pose(0.3, 0.0), pose(2.0, 0.0)]
    assert remove_passed(goals, pose(0.1, 0.0), 0.5) == goals[2:]
    assert remove_passed(goals, pose(5.0, 5.0), 0.5) == goals
    assert remove_passed(goals[2:], pose(2.0, 0.0), 0.5) == goals[2:]


def test_truncate_path_stops_short_and_faces_the_goal(tmp_path: Path) -> None:
    path = PathMsg(poses=[pose(0.1 * i, 0.0) for i in range(31)])  # 0.0 .. 3.0 m
    out = truncate(path, 1.0)
    assert out.poses[-1].pose.position.x == pytest.approx(2.0)
    assert len(path.poses) == 31  # the input is not changed
    last = out.poses[-1].pose.orientation
    assert 2 * math.atan2(last.z, last.w) == pytest.approx(0.0)
    assert len(truncate(PathMsg(poses=path.poses[:3]), 10.0).poses) == 2
    root = leaf_of(tmp_path, 'TruncatePath: {input_path: "{p}", output_path: "{q}", '
                             'distance: 0.5}',
                   "blackboard:\n  p: {type: nav_msgs/msg/Path}\n"
                   "  q: {type: nav_msgs/msg/Path}\n")
    Blackboard.storage["/p"] = path
    assert tick(root) == Status.SUCCESS
    assert Blackboard.storage["/q"].poses[-1].pose.position.x == pytest.approx(2.5)
