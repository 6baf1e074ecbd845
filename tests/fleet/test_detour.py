"""Planning next to other robots, without ROS: NavFn's tolerance, the clearance, head-on.

- a zone under a robot's body (a robot killed there) is reached as NavFn reaches it: the
  path ends at the nearest reachable free cell within the tolerance square;
- the global costmap's robots and the controller's contact rule agree: a path planned next
  to another robot never comes within the contact distance, so it can be driven to its end;
- two robots meeting head-on in a passage both fail to make progress, and the fleet tree's
  back-off (BackUp 0.5 m, then a random 1-9 s dwell) lets the first to try again through.
"""

from __future__ import annotations

import itertools
import math
import random
from collections.abc import Callable, Iterator, Sequence

import pytest

from sar_framework.sim.costmaps import Costmaps
from sar_framework.sim.detour import plan_legs
from sar_framework.sim.drive import DiffDrive
from sar_framework.sim.faults import Circle, with_circles
from sar_framework.sim.goals import ERROR_NONE, FOLLOW_PATH_NO_PROGRESS, Goal, Outcome
from sar_framework.sim.navigation import Navigator
from sar_framework.sim.occupancy import DEFAULT_MAP_PREFIX, load_map
from sar_framework.sim.planner import GridPlanner, NoPath
from sar_framework.sim.traffic import CLEARANCE_M, Traffic, padding
from sar_framework.sim.world import Pose2D

MAP_YAML = DEFAULT_MAP_PREFIX.with_name(DEFAULT_MAP_PREFIX.name + ".yaml")
RADIUS = 0.22
CONTACT = 2 * RADIUS + CLEARANCE_M
ZONES = {"zone_a": (-3.0, 3.0), "zone_b": (3.5, 3.0), "zone_c": (4.0, -3.0),
         "zone_d": (-3.5, -3.0)}
BACKUP_M = 0.5  # trees/fleet_search.yaml's BackUp
HOMES = [(4.5, 1.0), (-4.5, 1.0), (-4.5, -1.0)]  # tests/fleet/fleet_mission.py's spawns


@pytest.fixture(scope="module")
def planner() -> GridPlanner:
    return GridPlanner(load_map(MAP_YAML), robot_radius=RADIUS)


def navigator(planner: GridPlanner, spawn: Pose2D, others: Sequence[tuple[float, float]] = (),
              traffic: Traffic | None = None) -> Navigator:
    traffic = traffic or Traffic(RADIUS)
    traffic.update([Circle(x, y, RADIUS) for x, y in others], 0.0)
    costmaps = Costmaps(planner.grid, RADIUS, planner=planner, traffic=traffic)
    return Navigator(DiffDrive(spawn), costmaps.planner(), costmaps=costmaps, traffic=traffic)


def drive(nav: Navigator, goal: Goal, limit_s: float = 120.0) -> None:
    now = 0.0
    while goal.active and now < limit_s:
        now += 0.05
        nav.step(0.05, now)


@pytest.mark.parametrize("offset", [(0.0, 0.0), (0.15, -0.1), (-0.2, 0.0), (0.0, 0.2)],
                         ids=["on_the_pose", "off_ne", "off_w", "off_n"])
@pytest.mark.parametrize("zone", sorted(ZONES))
def test_a_zone_under_a_dead_robot_is_reached_at_navfns_approach_point(
        planner: GridPlanner, zone: str, offset: tuple[float, float]) -> None:
    """Failed before: 206 (goal inside the body) or 105 (held short of the path's end)."""
    zx, zy = ZONES[zone]
    body = (zx + offset[0], zy + offset[1])
    for home in HOMES:
        nav = navigator(planner, Pose2D(*home), [body])
        goal = nav.start(Pose2D(zx, zy, 0.0))
        end = goal.path[-1] if goal.path else None
        drive(nav, goal)
        assert goal.outcome is Outcome.SUCCEEDED, (home, goal.error_code, goal.error_msg)
        assert end is not None and max(abs(end[0] - zx), abs(end[1] - zy)) <= 0.5  # NavFn
        assert math.dist(end, body) >= CONTACT
        pose = nav.state().pose
        assert math.dist((pose.x, pose.y), end) <= 0.25  # xy_goal_tolerance of the path end


def test_a_goal_under_a_robot_with_no_free_cell_in_the_tolerance_has_no_path(
        planner: GridPlanner) -> None:
    body = Circle(3.5, 3.0, RADIUS + padding(planner.grid.resolution))
    tight = GridPlanner(with_circles(planner.grid, [body]), robot_radius=RADIUS,
                        goal_tolerance=0.3)
    with pytest.raises(NoPath, match="another robot covers it"):
        plan_legs(tight, [body], Pose2D(4.5, 1.0), [Pose2D(3.5, 3.0)])
    assert NoPath.error_code == 208  # ComputePathToPose NO_VALID_PATH, as NavFn's planner


def points_along(path: Sequence[tuple[float, float]], step: float = 0.01
                 ) -> Iterator[tuple[float, float]]:
    for (ax, ay), (bx, by) in itertools.pairwise(path):
        n = max(int(math.dist((ax, ay), (bx, by)) / step), 1)
        for i in range(n + 1):
            yield ax + (bx - ax) * i / n, ay + (by - ay) * i / n


def test_paths_planned_next_to_a_robot_keep_the_controllers_contact_distance(
        planner: GridPlanner) -> None:
    """The costmap's robots are padded: no path point comes within the contact rule."""
    checked = 0
    for other in [(2.0, 2.5), (-2.5, 2.0), (2.0, -2.0), (-3.0, -1.5), (0.5, 1.0)]:
        nav = navigator(planner, Pose2D(0.0, 0.0), [other])
        for angle in range(0, 360, 20):
            for ring in (0.6, 1.0):
                start = Pose2D(other[0] + ring * math.cos(math.radians(angle)),
                               other[1] + ring * math.sin(math.radians(angle)))
                if not nav.is_free(start.x, start.y):
                    continue
                for tx, ty in [(other[0] + 1.2, other[1]), (other[0], other[1] - 1.2),
                               (other[0] - 1.2, other[1] + 0.3)]:
                    if not nav.is_free(tx, ty):
                        continue
                    path = nav.plan_through(start, [Pose2D(tx, ty)])[0]
                    closest = min(math.dist(p, other) for p in points_along(path))
                    assert closest >= CONTACT, (other, start, (tx, ty), closest)
                    checked += 1
    assert checked > 100


@pytest.mark.parametrize(("start", "target"), [((1.2, 2.5), (2.8, 2.5)),
                                               ((2.0, 1.4), (2.0, 3.6))])
def test_a_robot_drives_to_the_end_of_a_path_planned_around_another(
        planner: GridPlanner, start: tuple[float, float], target: tuple[float, float]) -> None:
    nav = navigator(planner, Pose2D(*start), [(2.0, 2.5)])
    goal = nav.start(Pose2D(*target))
    drive(nav, goal)
    assert goal.outcome is Outcome.SUCCEEDED, goal.error_msg


def head_on(planner: GridPlanner, a: tuple[Pose2D, Pose2D], b: tuple[Pose2D, Pose2D],
            dwell: Callable[[int], float], limit_s: float = 300.0
            ) -> tuple[list[str], list[int]]:
    """Two robots, each running the fleet tree's HomeDespiteTraffic loop in plain Python.

    NavigateToBase, else BackUp 0.5 m at 0.25 m/s (skipped when a wall is behind, as the
    BackUp server's COLLISION_AHEAD) and Dwell ``dwell(robot index)`` seconds; then again.
    Returns each robot's end ("done" or where it was) and how many navigations failed.
    """
    traffic = [Traffic(RADIUS), Traffic(RADIUS)]
    navs = [navigator(planner, a[0], traffic=traffic[0]),
            navigator(planner, b[0], traffic=traffic[1])]
    targets = [a[1], b[1]]

    def see(now: float) -> None:
        pa, pb = navs[0].state().pose, navs[1].state().pose
        traffic[0].update([Circle(pb.x, pb.y, RADIUS)], now)
        traffic[1].update([Circle(pa.x, pa.y, RADIUS)], now)

    see(0.0)
    state = ["navigate", "navigate"]
    goals = [nav.start(target) for nav, target in zip(navs, targets, strict=True)]
    fails = [0, 0]
    now = 0.0
    while now < limit_s and state != ["done", "done"]:
        now += 0.05
        for nav in navs:
            nav.step(0.05, now)
        see(now)
        for i, nav in enumerate(navs):
            if state[i] == "done" or goals[i].active:
                continue
            if state[i] == "navigate" and goals[i].outcome is Outcome.SUCCEEDED:
                state[i] = "done"
            elif state[i] == "navigate":
                # 105 held by the other, or 208 while the other still narrows the passage
                code = goals[i].error_code
                assert code in (FOLLOW_PATH_NO_PROGRESS, NoPath.error_code), goals[i].error_msg
                fails[i] += 1
                here = nav.state().pose
                end = Pose2D(here.x - BACKUP_M * math.cos(here.yaw),
                             here.y - BACKUP_M * math.sin(here.yaw), here.yaw)
                if not nav.path_is_clear(here, end):  # BackUp's COLLISION_AHEAD: dwell anyway
                    state[i], goals[i] = "dwell", nav.start_wait(dwell(i))
                    continue
                state[i], goals[i] = "back_up", nav.start_straight(-BACKUP_M, 0.25, 10.0,
                                                                   ERROR_NONE)
            elif state[i] == "back_up":
                state[i], goals[i] = "dwell", nav.start_wait(dwell(i))
            else:
                state[i], goals[i] = "navigate", nav.start(targets[i])
    return state, fails


NORTH_SOUTH = ((Pose2D(0.5, 2.0, -1.57), Pose2D(0.5, -2.0)),
               (Pose2D(0.5, -2.0, 1.57), Pose2D(0.5, 2.0)))
"""Head-on through the hub's opening at y = 0: too narrow to pass (or go around)."""


def tree_dwell(seed: int) -> Callable[[int], float]:
    """The fleet tree's Dwell: 1 s plus a jitter drawn from [0, 8] s, anew every time."""
    draws = [random.Random(seed * 2), random.Random(seed * 2 + 1)]
    return lambda robot: 1.0 + draws[robot].uniform(0.0, 8.0)


@pytest.mark.parametrize("seed", range(5))
def test_a_head_on_meeting_in_a_passage_is_resolved_by_the_trees_back_off(
        planner: GridPlanner, seed: int) -> None:
    state, fails = head_on(planner, *NORTH_SOUTH, tree_dwell(seed))
    assert state == ["done", "done"]
    assert min(fails) >= 1  # no way around in the passage: both failed to make progress
    assert max(fails) <= 4  # the tree allows 6


def test_a_head_on_meeting_with_the_same_dwell_repeats_itself(planner: GridPlanner) -> None:
    """Why the tree's dwell is random: the same tree on both robots would meet again."""
    state, fails = head_on(planner, *NORTH_SOUTH, lambda _robot: 5.0, limit_s=100.0)
    assert state != ["done", "done"] and min(fails) >= 3


def test_two_robots_meeting_head_on_in_the_open_pass_each_other(planner: GridPlanner) -> None:
    state, fails = head_on(planner, (Pose2D(1.5, 3.5), Pose2D(4.5, 3.5)),
                           (Pose2D(4.5, 3.5, math.pi), Pose2D(1.5, 3.5)), tree_dwell(0))
    assert state == ["done", "done"] and fails == [0, 0]
