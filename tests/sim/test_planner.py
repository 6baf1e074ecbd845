"""Grid planner: spec routes exist and stay clear, failures raise the right error, speed."""

import itertools
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from sar_plugins.sar.course_world import load_course_world

from sar_framework.sim.occupancy import DEFAULT_MAP_PREFIX, OCCUPIED, load_map, rasterize
from sar_framework.sim.planner import (
    GoalInObstacle,
    GridPlanner,
    NoPath,
    PlanningError,
    StartInObstacle,
)

BASE = (0.0, 0.0)
ZONES = {"zone_a": (-3.0, 3.0), "zone_b": (3.5, 3.0), "zone_c": (4.0, -3.0), "zone_d": (-3.5, -3.0)}
MAP_YAML = DEFAULT_MAP_PREFIX.with_name("final_project_map.yaml")


@pytest.fixture(scope="module")
def planner() -> GridPlanner:
    return GridPlanner(load_map(MAP_YAML), robot_radius=0.22)


def sample(a, b, step=0.005):
    n = max(2, math.ceil(math.dist(a, b) / step) + 1)
    t = np.linspace(0.0, 1.0, n)
    return a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t


def hits(planner, a, b, mask):
    xs, ys = sample(a, b)
    g = planner.grid
    cols = np.floor((xs - g.origin_x) / g.resolution).astype(int)
    rows = np.floor((ys - g.origin_y) / g.resolution).astype(int)
    return bool(mask[rows, cols].any())


def assert_safe(planner, path, start, goal):
    assert path[0] == pytest.approx(start)
    assert path[-1] == pytest.approx(goal)
    occupied = planner.grid.data == OCCUPIED
    for a, b in itertools.pairwise(path):
        assert not hits(planner, a, b, occupied), (a, b)
    # Only a leg that starts or ends at a blocked endpoint may enter the inflation.
    start_blocked = not planner.is_free(*start)
    goal_blocked = not planner.is_free(*goal)
    legs = list(itertools.pairwise(path))
    inner = legs[1 if start_blocked else 0 : len(legs) - (1 if goal_blocked else 0)]
    for a, b in inner:
        assert not hits(planner, a, b, planner.blocked), (a, b)


@pytest.mark.parametrize("zone", sorted(ZONES))
@pytest.mark.parametrize("outbound", [True, False], ids=["base_to_zone", "zone_to_base"])
def test_routes_between_base_and_zones(planner, zone, outbound):
    start, goal = (BASE, ZONES[zone]) if outbound else (ZONES[zone], BASE)
    path = planner.plan(start, goal)
    assert_safe(planner, path, start, goal)
    length = sum(math.dist(a, b) for a, b in itertools.pairwise(path))
    assert math.dist(start, goal) <= length < 1.5 * math.dist(start, goal) + 1.0
    assert len(path) <= 8  # shortcut, not a staircase of cells


def test_base_is_in_the_inflation_and_is_escaped(planner):
    assert not planner.is_free(*BASE)  # 0.075 m from the end of wall_h_left
    path = planner.plan(BASE, ZONES["zone_b"])
    assert planner.is_free(*path[1])
    assert math.dist(path[0], path[1]) < 0.25


def test_start_hugging_a_wall_escapes(planner):
    start = (-3.0, 0.2)  # 0.125 m from wall_h_left's face
    path = planner.plan(start, ZONES["zone_a"])
    assert_safe(planner, path, start, ZONES["zone_a"])


@pytest.mark.parametrize("goal", [(-3.0, 0.0), (0.0, 5.0), (3.0, -3.0), (-2.0, -2.5)])
def test_goal_in_wall_or_debris(planner, goal):
    with pytest.raises(GoalInObstacle, match="inside an obstacle"):
        planner.plan(BASE, goal)


def test_goal_outside_the_map(planner):
    with pytest.raises(GoalInObstacle, match="outside the map"):
        planner.plan(BASE, (20.0, 0.0))


def test_start_outside_or_inside_obstacle(planner):
    with pytest.raises(StartInObstacle, match="outside the map"):
        planner.plan((-20.0, 0.0), BASE)
    with pytest.raises(StartInObstacle, match="inside an obstacle"):
        planner.plan((0.0, 5.0), BASE)


def test_goal_beyond_the_arena_wall(planner):
    # map_server reads the unknown margin as free: reachable cells but a sealed region
    with pytest.raises(NoPath, match="separate free regions"):
        planner.plan(BASE, (6.3, 0.0))
    raw = GridPlanner(rasterize(load_course_world().world))
    with pytest.raises(GoalInObstacle):  # the rasterised grid keeps it unknown
        raw.plan(BASE, (6.3, 0.0))


def test_goal_near_wall_is_approached_within_tolerance(planner):
    goal = (-3.0, 0.15)  # 0.075 m from a wall face: inflated but not occupied
    path = planner.plan(ZONES["zone_a"], goal)
    assert_safe(planner, path, ZONES["zone_a"], goal)
    tight = GridPlanner(planner.grid, goal_tolerance=0.05)
    with pytest.raises(GoalInObstacle, match="no free cell"):
        tight.plan(ZONES["zone_a"], goal)


def test_errors_share_a_base_class():
    assert issubclass(GoalInObstacle, PlanningError)
    assert issubclass(NoPath, PlanningError)
    assert issubclass(StartInObstacle, PlanningError)


def test_same_cell_and_determinism(planner):
    assert planner.plan((-3.0, 3.0), (-3.01, 3.01)) == [(-3.0, 3.0), (-3.01, 3.01)]
    assert planner.plan(BASE, ZONES["zone_d"]) == planner.plan(BASE, ZONES["zone_d"])


free_points = st.tuples(st.floats(-5.7, 5.7), st.floats(-4.7, 4.7))


@settings(max_examples=25, deadline=None)
@given(start=free_points, goal=free_points)
def test_property_plans_are_safe(planner, start, goal):
    try:
        path = planner.plan(start, goal)
    except (StartInObstacle, GoalInObstacle):
        return
    assert_safe(planner, path, start, goal)
