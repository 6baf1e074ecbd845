"""Diff-drive model and path follower: arrival, limits, yaw wrap, safety, progress."""

import itertools
import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from sar_framework.sim.drive import DiffDrive, DriveLimits, Phase, normalize_angle
from sar_framework.sim.occupancy import DEFAULT_MAP_PREFIX, OCCUPIED, load_map
from sar_framework.sim.planner import GridPlanner
from sar_framework.sim.world import Pose2D

ZONES = {
    "zone_a": (-3.0, 3.0, 0.0),
    "zone_b": (3.5, 3.0, 1.57),
    "zone_c": (4.0, -3.0, 3.14),
    "zone_d": (-3.5, -3.0, -1.57),
}
BASE = (0.0, 0.0, 0.0)


@pytest.fixture(scope="module")
def planner() -> GridPlanner:
    return GridPlanner(load_map(DEFAULT_MAP_PREFIX.with_name("final_project_map.yaml")))


def yaw_error(a, b):
    return abs(normalize_angle(a - b))


def drive_to(robot, planner, goal, dt=0.05, limit=120.0):
    """Plan and drive to goal=(x, y, yaw); returns (sim time, [(pose, v, w)])."""
    pose = robot.pose
    robot.follow(planner.plan((pose.x, pose.y), goal[:2]), goal[2])
    t, trace = 0.0, []
    while robot.active and t < limit:
        v, w = robot.step(dt)
        t += dt
        trace.append((robot.pose, v, w))
    return t, trace


def test_base_to_zone_a_within_tolerance_in_plausible_time(planner):
    robot = DiffDrive(Pose2D(0.0, 0.0, 0.0))
    path = planner.plan((0.0, 0.0), ZONES["zone_a"][:2])
    length = sum(math.dist(a, b) for a, b in itertools.pairwise(path))
    t, _ = drive_to(robot, planner, ZONES["zone_a"])
    assert robot.succeeded and robot.phase is Phase.ARRIVED
    assert robot.within_tolerance()
    pose = robot.pose
    assert math.dist((pose.x, pose.y), ZONES["zone_a"][:2]) <= 0.25
    assert yaw_error(pose.yaw, 0.0) <= 0.25
    assert length / 0.5 <= t <= 2.0 * length / 0.5 + 8.0
    assert robot.odometry == pytest.approx(length, rel=0.1)


@pytest.mark.parametrize("dt", [0.02, 0.05], ids=["50Hz", "20Hz"])
def test_mission_tour_is_safe_and_within_limits(planner, dt):
    occupied = planner.grid.data == OCCUPIED
    robot = DiffDrive(Pose2D(0.0, 0.0, 0.0))
    for name in [*ZONES, "base"]:
        goal = BASE if name == "base" else ZONES[name]
        _, trace = drive_to(robot, planner, goal, dt=dt)
        assert robot.succeeded, name
        pose = robot.pose
        assert math.dist((pose.x, pose.y), goal[:2]) <= 0.25, name
        assert yaw_error(pose.yaw, goal[2]) <= 0.25, name
        for p, v, w in trace:
            assert 0.0 <= v <= 0.5 + 1e-12
            assert abs(w) <= 1.0 + 1e-12
            row, col = planner.grid.world_to_cell(p.x, p.y)
            assert not occupied[row, col], (name, p)


def test_custom_limits_are_respected(planner):
    limits = DriveLimits(max_linear=0.3, max_angular=0.5)
    robot = DiffDrive(Pose2D(0.0, 0.0, 0.0), limits)
    _, trace = drive_to(robot, planner, ZONES["zone_c"], limit=200.0)
    assert robot.succeeded
    assert max(v for _, v, _ in trace) == pytest.approx(0.3)
    assert max(abs(w) for _, _, w in trace) <= 0.5 + 1e-12


@pytest.mark.parametrize("zone", ["zone_c", "zone_d"])
def test_goal_yaw_near_pi_and_minus_half_pi(planner, zone):
    robot = DiffDrive(Pose2D(0.0, 0.0, 0.0))
    drive_to(robot, planner, ZONES[zone])
    assert robot.succeeded
    assert -math.pi <= robot.pose.yaw < math.pi
    assert yaw_error(robot.pose.yaw, ZONES[zone][2]) <= 0.25


def test_rotation_takes_the_short_way_across_pi():
    robot = DiffDrive(Pose2D(1.0, 1.0, 3.1))
    robot.follow([(1.0, 1.0)], goal_yaw=-3.1)  # 0.083 rad away through +-pi
    turned, t = 0.0, 0.0
    while robot.active:
        _, w = robot.step(0.05)
        turned += abs(w) * 0.05
        t += 0.05
    assert robot.succeeded
    assert turned < 0.1
    assert t < 1.0
    assert yaw_error(robot.pose.yaw, -3.1) <= 0.02


def test_goal_behind_turns_in_place_first():
    robot = DiffDrive(Pose2D(0.0, 0.0, 0.0))
    robot.follow([(0.0, 0.0), (-2.0, 0.0)], goal_yaw=math.pi)
    v, w = robot.step(0.05)
    assert v == 0.0 and abs(w) > 0.0
    assert (robot.pose.x, robot.pose.y) == (0.0, 0.0)


def test_progress_reports(planner):
    robot = DiffDrive(Pose2D(0.0, 0.0, 0.0))
    path = planner.plan((0.0, 0.0), ZONES["zone_b"][:2])
    length = sum(math.dist(a, b) for a, b in itertools.pairwise(path))
    robot.follow(path, ZONES["zone_b"][2])
    assert robot.distance_remaining() == pytest.approx(length)
    eta = robot.estimated_time_remaining()
    assert eta >= length / 0.5
    previous = robot.distance_remaining()
    while robot.active:
        robot.step(0.05)
        remaining = robot.distance_remaining()
        assert remaining <= previous + 0.03  # small wobble at corners only
        previous = remaining
    assert robot.distance_remaining() == 0.0
    assert robot.estimated_time_remaining() == 0.0


def test_deterministic(planner):
    runs = []
    for _ in range(2):
        robot = DiffDrive(Pose2D(0.0, 0.0, 0.0))
        _, trace = drive_to(robot, planner, ZONES["zone_d"])
        runs.append(trace)
    assert runs[0] == runs[1]


def test_cancel_and_idle():
    robot = DiffDrive(Pose2D(0.0, 0.0, 0.0))
    assert robot.step(0.1) == (0.0, 0.0)
    assert not robot.active
    robot.follow([(3.0, 0.0)], goal_yaw=0.0)
    robot.step(0.1)
    robot.cancel()
    pose = robot.pose
    assert robot.step(0.1) == (0.0, 0.0)
    assert robot.pose == pose
    assert robot.phase is Phase.IDLE
    assert robot.odometry > 0.0


def test_bad_input():
    robot = DiffDrive()
    with pytest.raises(ValueError, match="dt"):
        robot.step(0.0)
    with pytest.raises(ValueError, match="empty"):
        robot.follow([], 0.0)
    with pytest.raises(ValueError, match="finite"):
        robot.follow([(math.nan, 0.0)], 0.0)
    with pytest.raises(ValueError, match=r"DriveLimits\.max_linear"):
        DriveLimits(max_linear=0.0)


@given(st.floats(min_value=-1e4, max_value=1e4, allow_nan=False))
def test_property_normalize_angle(angle):
    wrapped = normalize_angle(angle)
    assert -math.pi <= wrapped < math.pi
    assert math.sin(wrapped) == pytest.approx(math.sin(angle), abs=1e-9)
    assert math.cos(wrapped) == pytest.approx(math.cos(angle), abs=1e-9)


@pytest.mark.parametrize("path", [
    [(-0.2, 0.0), (0.5, 0.0), (1.0, 0.0), (2.0, 0.0)],  # re-planned from a pose passed
    [(-0.5, 0.0), (2.0, 0.0)],
    [(-1.0, 0.0), (-0.5, 0.0), (2.0, 0.0)],
    [(-0.3, 0.1), (0.3, 0.1), (2.0, 0.0)],
])
def test_a_path_that_starts_behind_the_robot_is_followed_from_the_nearest_point(path):
    """Bug: the robot drove back to the path's first pose and circled there forever.

    Nav2's controllers prune the plan up to the pose nearest the robot; so does follow().
    """
    robot = DiffDrive(Pose2D(0.0, 0.0, 0.0))
    robot.follow(path, 0.0)
    t, xs = 0.0, []
    while robot.active and t < 30.0:
        robot.step(0.05)
        t += 0.05
        xs.append(robot.pose.x)
    assert robot.succeeded, (robot.phase, robot.pose)
    assert t < 8.0
    assert min(xs) > -0.05  # never drove back to the path's start
    assert math.dist((robot.pose.x, robot.pose.y), (2.0, 0.0)) <= 0.25


def test_a_path_through_the_robot_later_is_not_cut_short():
    """The nearest point is searched near the path's start only: a loop is driven whole."""
    loop = [(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0), (0.0, 0.2), (1.0, 0.2)]
    robot = DiffDrive(Pose2D(0.0, 0.0, 0.0))
    robot.follow(loop, 0.0)
    assert robot.distance_remaining() == pytest.approx(8.8, abs=0.01)


# Recorded from the flaky ROS test (DistanceController re-plans, FollowPath): a path planned
# from a pose the robot had already passed, going round a corner the robot cuts.
DOUBLING_BACK = [
    (0.1371, 0.1734), (0.1679, 0.1341), (0.175, 0.125), (0.175, 0.075), (0.175, 0.025),
    (0.175, -0.025), (0.175, -0.025), (0.1255, -0.0179), (0.076, -0.0109), (0.0265, -0.0038),
    (0.0, 0.0),
]


def test_a_path_left_across_a_corner_is_still_finished():
    """Bug: the follower's place on the path stayed on its first segment when the robot cut
    across the corner of a path that doubles back, so its carrot stopped on a point the
    robot then reached; it spun on that point, 0.04 m from the goal, forever.

    Nav2's controllers re-prune the plan to the pose nearest the robot every cycle.
    """
    robot = DiffDrive(Pose2D(0.1335, 0.0972, -1.9227))
    robot.follow(DOUBLING_BACK, 0.0)
    t = 0.0
    while robot.active and t < 30.0:
        robot.step(0.02)
        t += 0.02
    assert robot.succeeded, (robot.phase, robot.pose)
    assert robot.within_tolerance()
    assert t < 8.0  # ~1 s of driving, ~3 s turning to the goal yaw
