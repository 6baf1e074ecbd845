"""The costmaps' phantom layer: clearing entirely, around the robot, except a region."""

from __future__ import annotations

import math

import pytest
import yaml

from sar_framework.sim import plugin_ids
from sar_framework.sim.costmaps import Costmaps, Layer
from sar_framework.sim.faults import Circle, FaultConfigError, parse_circles, with_circles
from sar_framework.sim.occupancy import load_map
from sar_framework.sim.params import DEFAULT_MAP_YAML
from sar_framework.sim.planner import GoalInObstacle

NEAR = Circle(0.6, 0.0, 0.2, "near")
FAR = Circle(1.0, -1.5, 0.3, "far")
WALL = Circle(2.0, -0.5, 0.3, "wall")


@pytest.fixture(scope="module")
def base():
    grid = load_map(DEFAULT_MAP_YAML)
    return with_circles(grid, [WALL])


@pytest.fixture
def costmaps(base) -> Costmaps:
    return Costmaps(base, 0.22, [NEAR, FAR])


def test_phantoms_are_written_into_both_costmaps_and_block_the_global_planner(costmaps):
    assert costmaps.phantoms(Layer.GLOBAL) == costmaps.phantoms(Layer.LOCAL) == (NEAR, FAR)
    with pytest.raises(GoalInObstacle):
        costmaps.planner().plan((0.0, 0.0), (1.0, -1.5))
    assert costmaps.local_blocks([(0.0, 0.0), (1.0, 0.0)]) == NEAR
    assert costmaps.local_blocks([(0.0, 0.0), (0.0, -1.0)]) is None


def test_clearing_entirely_one_costmap_leaves_the_other_and_the_walls(costmaps):
    assert costmaps.clear(Layer.GLOBAL) == 2
    assert costmaps.phantoms(Layer.LOCAL) == (NEAR, FAR)
    assert costmaps.planner().plan((0.0, 0.0), (1.0, -1.5))[-1] == pytest.approx((1.0, -1.5))
    with pytest.raises(GoalInObstacle):
        costmaps.planner().plan((0.0, 0.0), (2.0, -0.5))  # blocked_areas stay


def test_around_the_robot_and_except_a_region_use_nav2s_square(costmaps):
    assert costmaps.clear_around(Layer.LOCAL, (0.0, 0.0), 1.0) == 0  # NEAR at 0.6 > 0.5
    assert costmaps.clear_around(Layer.LOCAL, (0.0, 0.0), 1.4) == 1
    assert costmaps.phantoms(Layer.LOCAL) == (FAR,)
    assert costmaps.clear_except(Layer.GLOBAL, (0.0, 0.0), 1.4) == 1
    assert costmaps.phantoms(Layer.GLOBAL) == (NEAR,)
    costmaps.write([FAR])
    assert costmaps.phantoms(Layer.GLOBAL) == costmaps.phantoms(Layer.LOCAL) == (FAR,)


def test_a_malformed_phantom_names_the_parameter():
    with pytest.raises(FaultConfigError, match="phantom_obstacles: '1:2'"):
        parse_circles(["1:2"], {}, "phantom_obstacles")
    assert parse_circles(["", "shelf"], {"shelf": (3.5, 3.0)}, "phantom_obstacles")[0].x == 3.5


def test_the_plugin_ids_are_the_params_files():
    params = yaml.safe_load((DEFAULT_MAP_YAML.parents[1] / "config" / "nav2_params.yaml")
                            .read_text())
    controller = params["controller_server"]["ros__parameters"]
    assert tuple(controller["controller_plugins"]) == plugin_ids.CONTROLLERS
    assert tuple(controller["goal_checker_plugins"]) == plugin_ids.GOAL_CHECKERS
    assert tuple(controller["progress_checker_plugins"]) == plugin_ids.PROGRESS_CHECKERS
    assert controller["progress_checker"]["movement_time_allowance"] == 10.0  # our default
    planners = params["planner_server"]["ros__parameters"]["planner_plugins"]
    assert tuple(planners) == plugin_ids.PLANNERS
    smoothers = params["smoother_server"]["ros__parameters"]["smoother_plugins"]
    assert tuple(smoothers) == plugin_ids.SMOOTHERS
    assert plugin_ids.unknown_id("", plugin_ids.PLANNERS, "planner") is None
    assert "'Nope' is not loaded" in plugin_ids.unknown_id("Nope", plugin_ids.PLANNERS,
                                                          "planner")


def test_a_phantom_around_the_robot_or_across_the_way_gives_nav2s_codes(base):
    from sar_framework.sim.planner import NoPath, StartInObstacle

    with pytest.raises(StartInObstacle) as start:
        Costmaps(base, 0.22, [Circle(0.0, 0.0, 0.3)]).planner().plan((0.0, 0.0),
                                                                          (1.0, -0.5))
    assert start.value.error_code == 205  # START_OCCUPIED
    ring = [Circle(1.0 + 0.8 * math.cos(a / 20 * math.tau),
                        -0.5 + 0.8 * math.sin(a / 20 * math.tau), 0.15) for a in range(20)]
    with pytest.raises(NoPath) as cut:  # the goal is free, but fenced in
        Costmaps(base, 0.22, ring).planner().plan((0.0, 0.0), (1.0, -0.5))
    assert cut.value.error_code == 208  # NO_VALID_PATH


def test_walls_can_be_replaced_and_never_clear(base):
    costmaps = Costmaps(base, 0.22, [FAR])
    costmaps.set_walls([Circle(1.0, -0.5, 0.3)])
    costmaps.clear(Layer.GLOBAL)
    with pytest.raises(GoalInObstacle):
        costmaps.planner().plan((0.0, 0.0), (1.0, -0.5))
    assert costmaps.planner().plan((0.0, 0.0), (1.0, -1.5))[-1] == pytest.approx((1.0, -1.5))
    costmaps.write([FAR])
    costmaps.set_walls([])
    assert costmaps.planner().plan((0.0, 0.0), (1.0, -0.5))[-1] == pytest.approx((1.0, -0.5))
    with pytest.raises(GoalInObstacle):
        costmaps.planner().plan((0.0, 0.0), (1.0, -1.5))  # the phantom is back
