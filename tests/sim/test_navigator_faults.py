"""The navigator's faults: a stuck controller, local costmap phantoms, reset."""

from __future__ import annotations

import pytest

from sar_framework.sim.costmaps import Costmaps, Layer
from sar_framework.sim.drive import DiffDrive
from sar_framework.sim.faults import Circle, Faults
from sar_framework.sim.goals import Outcome
from sar_framework.sim.navigation import Navigator
from sar_framework.sim.occupancy import DEFAULT_MAP_PREFIX, load_map
from sar_framework.sim.world import Pose2D

MAP_YAML = DEFAULT_MAP_PREFIX.with_name(DEFAULT_MAP_PREFIX.name + ".yaml")
GOAL = Pose2D(1.0, -0.5, 0.0)


@pytest.fixture(scope="module")
def grid():
    return load_map(MAP_YAML)


def navigator(grid, faults: Faults | None = None, phantoms=()) -> Navigator:
    costmaps = Costmaps(grid, 0.22, phantoms)
    return Navigator(DiffDrive(Pose2D(0.0, 0.0, 0.0)), costmaps.planner(), faults,
                     costmaps=costmaps)


def run(nav: Navigator, goal, start: float = 0.0, limit_s: float = 60.0,
        dt: float = 0.02) -> float:
    now = start
    while goal.active and now < start + limit_s:
        now += dt
        nav.step(dt, now)
    return now


def test_a_stuck_controller_fails_after_the_allowance_until_recoveries_free_it(grid) -> None:
    nav = navigator(grid, Faults(stuck_recoveries=2, movement_time_allowance=3.0))
    goal = nav.start(GOAL)
    now = run(nav, goal)
    assert goal.outcome is Outcome.ABORTED and goal.error_code == 105
    assert goal.finished_s == pytest.approx(3.0, abs=0.05)
    assert nav.state().pose == Pose2D(0.0, 0.0, 0.0)  # never moved
    for _ in range(2):
        now = run(nav, nav.start_spin(0.5, 0.0, 701), now)
        assert nav.stuck_left < 2
    assert nav.stuck_left == 0
    now = run(nav, nav.start_wait(0.5), now)  # a wait frees nothing: only motions count
    goal = nav.start_path([(nav.state().pose.x, nav.state().pose.y), (1.0, -0.5)], GOAL)
    run(nav, goal, now)
    assert goal.outcome is Outcome.SUCCEEDED


def test_a_path_through_a_local_phantom_has_no_valid_control_until_cleared(grid) -> None:
    phantom = Circle(0.5, -0.25, 0.2)
    nav = navigator(grid, phantoms=[phantom])
    goal = nav.start_path([(0.0, 0.0), (1.0, -0.5)], GOAL)
    assert goal.outcome is Outcome.ABORTED and goal.error_code == 106
    assert "local costmap" in goal.error_msg
    assert not nav.path_is_clear(Pose2D(0.0, 0.0, 0.0), GOAL)
    nav.costmaps.clear(Layer.LOCAL)
    goal = nav.start_path([(0.0, 0.0), (1.0, -0.5)], GOAL)
    run(nav, goal)
    assert goal.outcome is Outcome.SUCCEEDED


def test_reset_aborts_puts_the_robot_back_and_restarts_goal_numbers(grid) -> None:
    nav = navigator(grid, Faults(abort_goal_numbers=frozenset({2}), abort_delay_s=0.5))
    first = nav.start(GOAL)
    run(nav, first, limit_s=1.0)
    assert first.active and nav.state().pose.x > 0.1
    generation = nav.generation
    assert nav.reset(Pose2D(0.0, 0.0, 0.0), "reset") is first
    assert first.outcome is Outcome.ABORTED and first.error_msg == "reset"
    assert nav.state().pose == Pose2D(0.0, 0.0, 0.0) and nav.state().linear == 0.0
    assert nav.generation == generation + 1 and nav.current is None
    again = nav.start(GOAL)
    assert again.number == 1  # goal 2 aborts again after the reset, not goal 1
    run(nav, again, 1.0)
    assert again.outcome is Outcome.SUCCEEDED
    second = nav.start(Pose2D(0.0, 0.0, 0.0))
    run(nav, second, 30.0)
    assert second.outcome is Outcome.ABORTED and second.number == 2


def test_a_new_path_for_a_running_follow_path_keeps_the_progress_clock(grid) -> None:
    # Nav2's controller server resets its progress checker when a goal starts, not when a
    # new path preempts the running one (updateGlobalPath): replanning does not restart it.
    nav = navigator(grid, Faults(stuck_recoveries=1, movement_time_allowance=3.0))
    path = [(0.0, 0.0), (1.0, -0.5)]
    first = nav.start_path(path, GOAL)
    now = run(nav, first, limit_s=2.0)
    second = nav.start_path(path, GOAL)  # a replanned path, 2 s into the allowance
    assert first.outcome is Outcome.ABORTED
    now = run(nav, second, now)
    assert second.outcome is Outcome.ABORTED and second.error_code == 105
    assert second.finished_s == pytest.approx(3.0, abs=0.05)
    third = nav.start_path(path, GOAL)  # a new goal once the last has ended: a fresh clock
    run(nav, third, now)
    assert third.error_code == 105 and third.finished_s == pytest.approx(6.0, abs=0.05)
