"""Other robots as obstacles, without ROS: the controller stops, the planner goes around."""

from __future__ import annotations

import math

import pytest

from sar_framework.sim.costmaps import Costmaps
from sar_framework.sim.drive import DiffDrive
from sar_framework.sim.faults import Circle
from sar_framework.sim.goals import FOLLOW_PATH_NO_PROGRESS, Outcome
from sar_framework.sim.navigation import Navigator
from sar_framework.sim.occupancy import DEFAULT_MAP_PREFIX, load_map
from sar_framework.sim.planner import GridPlanner, PlanningError
from sar_framework.sim.traffic import CLEARANCE_M, Traffic
from sar_framework.sim.world import Pose2D

MAP_YAML = DEFAULT_MAP_PREFIX.with_name(DEFAULT_MAP_PREFIX.name + ".yaml")
RADIUS = 0.22


@pytest.fixture(scope="module")
def planner() -> GridPlanner:
    return GridPlanner(load_map(MAP_YAML), robot_radius=RADIUS)


def robot(planner: GridPlanner, spawn: Pose2D, other: Pose2D | None,
          traffic: Traffic | None = None) -> Navigator:
    traffic = traffic or Traffic(RADIUS)
    if other is not None:
        traffic.update([Circle(other.x, other.y, RADIUS, "other")], 0.0)
    costmaps = Costmaps(planner.grid, RADIUS, planner=planner, traffic=traffic)
    return Navigator(DiffDrive(spawn), costmaps.planner(), costmaps=costmaps, traffic=traffic)


def run(nav: Navigator, goal, limit_s: float = 60.0) -> float:
    now = 0.0
    while goal.active and now < limit_s:
        now += 0.02
        nav.step(0.02, now)
    return now


def test_ahead_sees_a_robot_in_front_in_contact_only() -> None:
    traffic = Traffic(RADIUS)
    traffic.update([Circle(1.0, 0.0, RADIUS)], 0.0)
    touching = 1.0 - 2 * RADIUS - CLEARANCE_M / 2
    assert traffic.ahead(Pose2D(touching, 0.0, 0.0)) is not None  # in front, in contact
    assert traffic.ahead(Pose2D(touching, 0.0, 3.14)) is None  # behind: it may drive away
    assert traffic.ahead(Pose2D(0.3, 0.0, 0.0)) is None  # not in contact yet


def test_the_global_costmap_sees_other_robots_at_its_update_rate() -> None:
    traffic = Traffic(RADIUS)
    traffic.update([Circle(1.0, 0.0, RADIUS)], 0.0)
    traffic.update([Circle(2.0, 0.0, RADIUS)], 0.5)  # live, not yet in the costmap
    assert traffic.in_costmap[0].x == 1.0
    assert traffic.ahead(Pose2D(2.0 - 2 * RADIUS, 0.0, 0.0)) is not None
    traffic.update([Circle(3.0, 0.0, RADIUS)], 1.0)
    assert traffic.in_costmap[0].x == 3.0


def test_a_robot_in_the_only_doorway_leaves_no_path(planner: GridPlanner) -> None:
    free = robot(planner, Pose2D(2.0, 1.0), None)
    assert free.planner.plan((2.0, 1.0), (4.0, -3.0))
    blocked = robot(planner, Pose2D(2.0, 1.0), Pose2D(0.5, 0.0))
    with pytest.raises(PlanningError):
        blocked.planner.plan((2.0, 1.0), (4.0, -3.0))


def test_the_planner_routes_around_a_robot_in_an_open_room(planner: GridPlanner) -> None:
    nav = robot(planner, Pose2D(2.0, 2.0), Pose2D(3.0, 2.0))
    path = nav.planner.plan((2.0, 2.0), (4.0, 2.0))
    assert min(abs(x - 3.0) + abs(y - 2.0) for x, y in path) > 2 * RADIUS
    goal = nav.start(Pose2D(4.0, 2.0))
    run(nav, goal)
    assert goal.outcome is Outcome.SUCCEEDED


def test_a_robot_that_moves_into_the_only_passage_stops_the_other_then_fails_it(
        planner: GridPlanner) -> None:
    """The costmap planned before the other robot came; the controller stops, no detour."""
    traffic = Traffic(RADIUS)
    nav = robot(planner, Pose2D(2.0, 1.0), None, traffic)
    goal = nav.start(Pose2D(4.0, -3.0))
    nav.step(0.02, 0.02)
    traffic.update([Circle(0.5, 0.0, RADIUS)], 0.5)  # into the hub's opening at y=0
    ended = run(nav, goal)
    assert goal.outcome is Outcome.ABORTED
    assert goal.error_code == FOLLOW_PATH_NO_PROGRESS
    assert "another robot at (0.50, 0.00)" in goal.error_msg
    pose = nav.state().pose
    assert 2 * RADIUS < math.hypot(pose.x - 0.5, pose.y) < 2 * RADIUS + CLEARANCE_M
    assert ended == pytest.approx(10.0, abs=5.0)  # movement_time_allowance after contact


def test_a_held_robot_replans_around_a_robot_that_stepped_into_its_way_in_the_open(
        planner: GridPlanner) -> None:
    """Nav2 replans at 1 Hz: the held robot turns in place onto a detour, then drives."""
    traffic = Traffic(RADIUS)
    nav = robot(planner, Pose2D(2.0, 2.0), None, traffic)
    goal = nav.start(Pose2D(4.0, 2.0))
    nav.step(0.02, 0.02)
    traffic.update([Circle(3.0, 2.0, RADIUS)], 0.5)
    closest, now = 10.0, 0.02
    while goal.active and now < 60.0:
        now += 0.02
        nav.step(0.02, now)
        pose = nav.state().pose
        closest = min(closest, math.hypot(pose.x - 3.0, pose.y - 2.0))
    assert goal.outcome is Outcome.SUCCEEDED, goal.error_msg
    assert closest > 2 * RADIUS  # it stopped in contact and never drove into the other
    assert 2.0 < now < 20.0  # it did not wait out movement_time_allowance


