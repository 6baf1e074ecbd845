"""The navigator's other goals: through poses, a given path, spin, straight motion, wait."""

from __future__ import annotations

import math

import pytest

from sar_framework.sim.drive import DiffDrive
from sar_framework.sim.goals import Outcome
from sar_framework.sim.navigation import Navigator
from sar_framework.sim.occupancy import DEFAULT_MAP_PREFIX, load_map
from sar_framework.sim.planner import GridPlanner
from sar_framework.sim.world import Pose2D

MAP_YAML = DEFAULT_MAP_PREFIX.with_name(DEFAULT_MAP_PREFIX.name + ".yaml")
TIMEOUT_CODE = 701  # Spin.Result.TIMEOUT


@pytest.fixture(scope="module")
def planner() -> GridPlanner:
    return GridPlanner(load_map(MAP_YAML), robot_radius=0.22)


def run_until_done(nav: Navigator, goal, limit_s: float = 60.0, dt: float = 0.02) -> float:
    now = 0.0
    while goal.active and now < limit_s:
        now += dt
        nav.step(dt, now)
    return now


def test_through_poses_passes_each_and_counts_them_down(planner: GridPlanner) -> None:
    nav = Navigator(DiffDrive(Pose2D(0.0, 0.0, 0.0)), planner)
    goal = nav.start(Pose2D(1.0, -0.8, 0.0), via=[Pose2D(1.0, 0.8, 0.0)])
    assert goal.active and len(goal.legs) == 1
    assert nav.progress(goal).poses_remaining == 2
    counts, now = set(), 0.0
    while goal.active and now < 60.0:
        now += 0.02
        nav.step(0.02, now)
        counts.add(nav.progress(goal).poses_remaining)
    assert goal.outcome is Outcome.SUCCEEDED
    assert {2, 1} <= counts
    assert nav.state().odometry > 2.5  # went up to y=0.8, then down to y=-0.8


def test_through_poses_that_double_back(planner: GridPlanner) -> None:
    """Before: the joined path reversed on itself at the via pose and the robot spun there."""
    nav = Navigator(DiffDrive(Pose2D(1.0, 0.5, 0.0)), planner)
    goal = nav.start(Pose2D(0.0, 0.0, 0.0), via=[Pose2D(1.0, -0.5, 0.0)])
    run_until_done(nav, goal)
    assert goal.outcome is Outcome.SUCCEEDED


def test_follow_path_drives_the_given_path(planner: GridPlanner) -> None:
    nav = Navigator(DiffDrive(Pose2D(0.0, 0.0, 0.0)), planner)
    goal = nav.start_path([(0.0, 0.0), (1.0, 0.0)], Pose2D(1.0, 0.0, 0.0))
    run_until_done(nav, goal)
    assert goal.outcome is Outcome.SUCCEEDED
    assert nav.state().pose.x == pytest.approx(1.0, abs=0.25)


def test_spin_turns_by_the_angle_and_reports_it(planner: GridPlanner) -> None:
    nav = Navigator(DiffDrive(Pose2D(0.0, 0.0, 0.0)), planner)
    goal = nav.start_spin(1.57, 10.0, TIMEOUT_CODE)
    nav.step(0.5, 0.5)
    assert nav.progress(goal).motion_done == pytest.approx(0.5, abs=1e-6)
    run_until_done(nav, goal)
    assert goal.outcome is Outcome.SUCCEEDED
    assert nav.state().pose.yaw == pytest.approx(1.57, abs=1e-6)


def test_spin_times_out_with_the_given_code(planner: GridPlanner) -> None:
    nav = Navigator(DiffDrive(Pose2D(0.0, 0.0, 0.0)), planner)
    goal = nav.start_spin(6.0, 1.0, TIMEOUT_CODE)  # 1 rad/s: needs 6 s
    run_until_done(nav, goal)
    assert (goal.outcome, goal.error_code) == (Outcome.ABORTED, TIMEOUT_CODE)
    assert nav.state().angular == 0.0


def test_backup_drives_backwards(planner: GridPlanner) -> None:
    nav = Navigator(DiffDrive(Pose2D(0.0, 0.0, 0.0)), planner)
    goal = nav.start_straight(-0.15, 0.025, 10.0, 711)
    assert goal.target.x == pytest.approx(-0.15)
    run_until_done(nav, goal)
    assert goal.outcome is Outcome.SUCCEEDED
    assert nav.state().pose.x == pytest.approx(-0.15, abs=1e-6)
    assert goal.finished_s == pytest.approx(6.0, abs=0.05)


def test_wait_succeeds_after_the_time_and_a_new_goal_preempts(planner: GridPlanner) -> None:
    nav = Navigator(DiffDrive(Pose2D(0.0, 0.0, 0.0)), planner)
    goal = nav.start_wait(2.0)
    nav.step(0.5, 0.5)
    assert nav.progress(goal).time_left == pytest.approx(1.5)
    run_until_done(nav, goal)
    assert goal.outcome is Outcome.SUCCEEDED
    assert goal.finished_s == pytest.approx(2.0, abs=0.03)
    waiting = nav.start_wait(5.0)
    spin = nav.start_spin(math.pi / 2, 0.0, TIMEOUT_CODE)
    assert waiting.outcome is Outcome.ABORTED and spin.active
