"""Simulator core without ROS: clock pacing, fault settings, trace file, goal execution."""

import math

import numpy as np
import pytest

from sar_framework.sim.clock import NS_PER_S, SimClock, split_ns
from sar_framework.sim.drive import DiffDrive
from sar_framework.sim.faults import (
    DEFAULT_NAMED_RADIUS,
    FaultConfigError,
    make_faults,
    parse_circle,
    with_circles,
)
from sar_framework.sim.goals import ERROR_NONE, Outcome
from sar_framework.sim.navigation import Navigator
from sar_framework.sim.occupancy import DEFAULT_MAP_PREFIX, OCCUPIED, load_map
from sar_framework.sim.planner import GoalInObstacle, GridPlanner
from sar_framework.sim.trace import TraceWriter, read_trace
from sar_framework.sim.world import Pose2D

MAP_YAML = DEFAULT_MAP_PREFIX.with_name("final_project_map.yaml")
PLACES = {"shelf_a": (-3.0, 3.0), "shelf_b": (3.5, 3.0)}
SEAL_ZONE_A_ROOM = "-0.5:0.85:0.8"  # a disk over the north-west room's doorway


# ---------------------------------------------------------------------------- clock


def test_clock_paces_steps_by_speed() -> None:
    clock = SimClock(step_s=0.02, speed=10.0)
    clock.start(100.0)
    assert clock.due_steps(100.0) == 0
    assert clock.due_steps(100.1) == 50  # 0.1 s wall x 10 = 1 s simulated = 50 steps
    clock.advance(50)
    assert clock.now_s == pytest.approx(1.0)
    assert clock.due_steps(100.1) == 0
    assert clock.wall_until_next_step(100.1) == pytest.approx(0.002)
    assert clock.real_time_factor(100.1) == pytest.approx(10.0)


def test_clock_keeps_exact_nanoseconds_over_many_steps() -> None:
    clock = SimClock(step_s=0.02, speed=1.0)
    for _ in range(100_000):
        clock.advance()
    assert clock.now_ns == 2_000 * NS_PER_S
    assert split_ns(clock.now_ns + 5) == (2_000, 5)


def test_clock_drops_a_backlog_instead_of_bursting() -> None:
    clock = SimClock(step_s=0.02, speed=1.0, max_lag_wall_s=0.2)
    clock.start(0.0)
    assert clock.due_steps(5.0) == 10  # 250 steps owed, 10 allowed
    assert clock.dropped_steps == 240
    clock.advance(10)
    assert clock.due_steps(5.0) == 0
    assert clock.due_steps(5.04) == 2  # paced normally from the new anchor


def test_a_stall_bursts_at_most_the_lag_s_worth_at_any_speed() -> None:
    # A process stalled by a loaded machine: the simulated time it catches up at once
    # (one /clock gap) is bounded in wall seconds, so it scales with the speed and a tree
    # ticking on /clock never sees the world jump by seconds.
    for speed, most in ((10.0, 10), (20.0, 20), (100.0, 100)):
        clock = SimClock(step_s=0.02, speed=speed, max_lag_wall_s=0.02)
        clock.start(0.0)
        assert clock.due_steps(0.01) == speed * 0.01 / 0.02  # on time: all due steps
        clock.advance(clock.due_steps(0.01) or 0)
        assert clock.due_steps(0.5) == most  # 0.49 s of wall stall: 0.02 s worth
        assert clock.dropped_steps > 0


def test_clock_hold_forgets_the_time_spent() -> None:
    clock = SimClock(step_s=0.1, speed=1.0)
    clock.start(0.0)
    clock.hold()
    assert clock.due_steps(3.0) == 0  # re-anchored: the 3 s are not owed
    assert clock.due_steps(3.25) == 2


def test_clock_speed_change_reanchors() -> None:
    clock = SimClock(step_s=0.1, speed=1.0, max_lag_wall_s=10.0)
    clock.start(0.0)
    clock.advance(clock.due_steps(1.0))
    clock.speed = 4.0
    assert clock.due_steps(1.0) == 0
    assert clock.due_steps(1.5) == 20


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"step_s": 0.0, "speed": 1.0}, "step_s must be a positive number"),
    ({"speed": -1.0}, "speed must be > 0 and <= 1000, got -1.0"),
    ({"speed": math.inf}, "speed must be finite"),
    ({"speed": 0}, "speed must be > 0 and <= 1000, got 0")])
def test_clock_rejects_bad_settings(kwargs: dict, message: str) -> None:
    """The clock's rule for speed is the simulator's parameter's (sim/params.py: SPEED)."""
    with pytest.raises(ValueError, match=message):
        SimClock(**kwargs)


# ---------------------------------------------------------------------------- faults


def test_blocked_area_forms() -> None:
    for text in ("1.5:-2:0.4", " 1.5, -2, 0.4 ", "1.5 -2 0.4"):
        circle = parse_circle(text, PLACES)
        assert (circle.x, circle.y, circle.radius, circle.label) == (1.5, -2.0, 0.4, text)
    named = parse_circle("shelf_b", PLACES)
    assert (named.x, named.y, named.radius) == (3.5, 3.0, DEFAULT_NAMED_RADIUS)
    assert parse_circle("shelf_a:0.9", PLACES).radius == 0.9


@pytest.mark.parametrize(
    ("entry", "message"),
    [
        ("shelf_x", "known: shelf_a, shelf_b"),
        ("1:2", "expected 'x:y:radius'"),
        ("1:two:3", "'two' is not a number"),
        ("1:2:-3", "radius must be positive"),
        ("shelf_a:1:2", "expected 'name[:radius]'"),
        ("1:2:nan", "not finite"),
    ],
)
def test_blocked_area_errors_name_the_entry(entry: str, message: str) -> None:
    with pytest.raises(FaultConfigError, match="blocked_areas") as info:
        parse_circle(entry, PLACES)
    assert message in str(info.value)


def test_without_named_places_only_coordinates_are_taken() -> None:
    with pytest.raises(FaultConfigError, match=r"'shelf_a': expected 'x:y:radius'$"):
        parse_circle("shelf_a", {})


def test_make_faults_reads_ros_placeholders_as_empty() -> None:
    faults = make_faults(abort_goal_numbers=[0], blocked_areas=[""])
    assert not faults.any
    faults = make_faults(abort_goal_numbers=[2, 3], accept_delay_wall_s=0.5)
    assert faults.aborts(2) and not faults.aborts(1)
    assert faults.any
    assert faults.describe() == "abort goals [2, 3] after 1 s; accept after 0.5 s wall"
    assert make_faults().describe() == "none"
    with pytest.raises(FaultConfigError, match="1-based"):
        make_faults(abort_goal_numbers=[-1])
    with pytest.raises(FaultConfigError, match="accept_delay_wall_s"):
        make_faults(accept_delay_wall_s=-1.0)


def test_blocked_areas_occupy_a_copy_of_the_grid() -> None:
    grid = load_map(MAP_YAML)
    zone = parse_circle("2.0:-2.0:0.5", {})
    blocked = with_circles(grid, [zone])
    assert blocked.value_at(2.0, -2.0) == OCCUPIED
    assert blocked.value_at(2.0, -2.45) == OCCUPIED
    assert blocked.value_at(2.0, -2.6) != OCCUPIED
    assert grid.value_at(2.0, -2.0) != OCCUPIED  # the original is untouched
    changed = np.count_nonzero(blocked.data != grid.data)
    assert changed == pytest.approx(math.pi * 0.5**2 / grid.resolution**2, rel=0.1)


# ---------------------------------------------------------------------------- trace


def test_trace_samples_moving_poses_and_events(tmp_path) -> None:
    path = tmp_path / "out" / "trace.jsonl"
    trace = TraceWriter(path, sample_period_s=0.5)
    trace.event(0.0, "start", x=0.0, y=0.0, yaw=0.0)
    trace.pose(0.1, 0.0, 0.0, 0.0, 0.0)
    trace.pose(0.2, 0.1, 0.0, 0.0, 0.1)  # within the sampling period: skipped
    trace.pose(0.7, 0.3, 0.0, 0.0, 0.3)
    trace.pose(1.5, 0.3, 0.0, 0.0, 0.3)  # did not move: skipped
    trace.event(1.6, "succeeded", goal=1, x=1.234567, y=0.0, yaw=0.0, path_m=0.3)
    trace.close()
    trace.pose(2.0, 1.0, 0.0, 0.0, 1.0)  # after close: ignored
    lines = read_trace(path)
    assert [line.get("event") for line in lines] == ["start", None, None, "succeeded"]
    assert [line["sim_s"] for line in lines] == [0.0, 0.1, 0.7, 1.6]
    assert lines[3]["x"] == 1.2346
    assert lines[2] == {"sim_s": 0.7, "x": 0.3, "y": 0.0, "yaw": 0.0, "path_m": 0.3}


# ---------------------------------------------------------------------------- navigator


@pytest.fixture(scope="module")
def planner() -> GridPlanner:
    return GridPlanner(load_map(MAP_YAML), robot_radius=0.22)


def run(navigator: Navigator, seconds: float, dt: float = 0.02, t0: float = 0.0) -> float:
    """Step the navigator for ``seconds`` of simulated time; return the end time."""
    now = t0
    for _ in range(round(seconds / dt)):
        now += dt
        navigator.step(dt, now)
    return now


def test_navigator_reaches_zone_a_within_tolerance(planner: GridPlanner) -> None:
    events = []
    nav = Navigator(DiffDrive(Pose2D(0.0, 0.0, 0.0)), planner,
                    listener=lambda goal, now, robot: events.append((goal.outcome, now)))
    goal = nav.start(Pose2D(-3.0, 3.0, 0.0))
    assert goal.number == 1 and goal.active and not nav.planning
    assert len(goal.path) >= 2
    first = nav.progress(goal)
    run(nav, 1.0)
    assert nav.progress(goal).distance_remaining < first.distance_remaining
    run(nav, 60.0, t0=1.0)
    assert goal.outcome is Outcome.SUCCEEDED and goal.done.is_set()
    assert goal.error_code == ERROR_NONE
    pose = nav.state().pose
    assert math.hypot(pose.x + 3.0, pose.y - 3.0) <= 0.25
    assert abs(pose.yaw) <= 0.25
    assert 4.2 < nav.state().odometry < 6.0  # straight line is 4.24 m
    assert [e[0] for e in events] == [Outcome.ACTIVE, Outcome.SUCCEEDED]
    assert 5.0 < goal.finished_s < 30.0


def test_navigator_goal_in_a_wall_aborts_with_the_reason(planner: GridPlanner) -> None:
    nav = Navigator(DiffDrive(Pose2D(0.0, 0.0, 0.0)), planner)
    goal = nav.start(Pose2D(0.0, 3.0, 0.0))
    assert goal.outcome is Outcome.ABORTED
    assert goal.error_code == GoalInObstacle.error_code == 206  # ComputePathToPose GOAL_OCCUPIED
    assert "inside an obstacle" in goal.error_msg
    assert nav.state().linear == 0.0


def test_navigator_new_goal_preempts_with_an_empty_result(planner: GridPlanner) -> None:
    nav = Navigator(DiffDrive(Pose2D(0.0, 0.0, 0.0)), planner)
    first = nav.start(Pose2D(4.0, -3.0, 0.0))
    run(nav, 2.0)
    second = nav.start(Pose2D(0.0, 0.0, 0.0))
    assert first.outcome is Outcome.ABORTED
    assert (first.error_code, first.error_msg) == (ERROR_NONE, "")
    assert second.active and second.number == 2
    run(nav, 30.0, t0=2.0)
    assert second.outcome is Outcome.SUCCEEDED


def test_navigator_cancel_stops_the_robot(planner: GridPlanner) -> None:
    nav = Navigator(DiffDrive(Pose2D(0.0, 0.0, 0.0)), planner)
    goal = nav.start(Pose2D(4.0, -3.0, 0.0))
    now = run(nav, 3.0)
    assert nav.cancel(goal)
    assert goal.outcome is Outcome.CANCELED
    assert not nav.cancel(goal)
    stopped = nav.state().pose
    run(nav, 2.0, t0=now)
    assert nav.state().pose == stopped
    assert nav.state().linear == 0.0


def test_navigator_injected_abort_hits_only_the_nth_goal(planner: GridPlanner) -> None:
    faults = make_faults(abort_goal_numbers=[2], abort_delay_s=0.5)
    nav = Navigator(DiffDrive(Pose2D(0.0, 0.0, 0.0)), planner, faults)
    outcomes = []
    now = 0.0
    for target in (Pose2D(1.0, 0.8, 0.0), Pose2D(0.5, -0.8, 0.0), Pose2D(0.0, 0.0, 0.0)):
        goal = nav.start(target)
        now = run(nav, 20.0, t0=now)
        outcomes.append((goal.outcome, goal.error_msg))
    assert outcomes[0] == (Outcome.SUCCEEDED, "")
    assert outcomes[1][0] is Outcome.ABORTED
    assert "injected fault: goal 2" in outcomes[1][1]
    assert outcomes[2] == (Outcome.SUCCEEDED, "")


def test_navigator_blocked_doorway_means_no_path(planner: GridPlanner) -> None:
    grid = with_circles(planner.grid, [parse_circle(SEAL_ZONE_A_ROOM, {})])
    nav = Navigator(DiffDrive(Pose2D(0.0, 0.0, 0.0)), GridPlanner(grid, robot_radius=0.22))
    goal = nav.start(Pose2D(-3.0, 3.0, 0.0))
    assert goal.outcome is Outcome.ABORTED
    assert "no path" in goal.error_msg
    assert nav.start(Pose2D(3.5, 3.0, 1.57)).active  # other rooms stay reachable


def test_navigator_abort_active_at_shutdown(planner: GridPlanner) -> None:
    nav = Navigator(DiffDrive(Pose2D(0.0, 0.0, 0.0)), planner)
    assert nav.abort_active("bye") is None
    goal = nav.start(Pose2D(4.0, -3.0, 0.0))
    assert nav.abort_active("bye") is goal
    assert (goal.outcome, goal.error_code, goal.error_msg) == (
        Outcome.ABORTED, ERROR_NONE, "bye"
    )
