"""Planning next to the other robots of a fleet: NavFn's goal tolerance, and replanning.

Plain Python. Two things Nav2 does that a robot of a fleet needs:

- **The goal tolerance** (:func:`plan_legs`). NavFn (``tolerance: 0.5`` in
  config/nav2_params.yaml) plans to the goal when it can; otherwise it scans the square of
  half-side ``tolerance`` around the goal for the nearest point it can reach (a square, not
  a circle), and the path ENDS there (``smoothApproachToGoal`` appends that point, not the
  goal). The controller's goal checker tests the path's last pose, so NavigateToPose
  succeeds there. A goal that another robot covers (one stopped there) is reached that
  way: the path ends at the nearest reachable free cell of that square. A goal in a wall or
  a ``blocked_areas`` circle keeps the simulator's rule (:mod:`.planner`: GOAL_OCCUPIED, or
  the approach cell plus a straight leg to the goal).
- **Replanning** (:class:`Detour`). Nav2's default navigate_to_pose tree replans at 1 Hz
  (``RateController hz="1.0"`` around ``ComputePathToPose``); the simulator plans once per
  goal, and replans while another robot holds the robot, at the global costmap's rate and
  with the other robots where that costmap last saw them. A robot standing in an open room
  is driven around (the held robot turns in place towards the new path, then leaves); one
  standing in the only passage leaves no path, and the held robot fails as before
  (FAILED_TO_MAKE_PROGRESS after ``movement_time_allowance``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from sar_framework.sim.costmaps import Costmaps
from sar_framework.sim.drive import DiffDrive
from sar_framework.sim.faults import Circle
from sar_framework.sim.goals import Goal, Kind
from sar_framework.sim.planner import GridPlanner, NoPath, PlanningError
from sar_framework.sim.traffic import GLOBAL_UPDATE_S, Traffic
from sar_framework.sim.world import Pose2D

__all__ = ["Detour", "approach", "covered", "plan_legs"]

Point = tuple[float, float]


def covered(planner: GridPlanner, robots: Sequence[Circle], goal: Point) -> bool:
    """Whether another robot covers ``goal``: it is not free, and within a robot's reach.

    Reach: the robot's (padded) circle in the costmap plus this robot's radius and a cell.
    """
    if planner.is_free(*goal):
        return False
    reach = planner.robot_radius + planner.grid.resolution
    return any(math.hypot(z.x - goal[0], z.y - goal[1]) <= z.radius + reach for z in robots)


def approach(planner: GridPlanner, start: Point, goal: Point) -> list[Point]:
    """NavFn's tolerance: a path to the nearest free cell reachable from ``start``.

    The cells searched are those whose centre lies in the square of half-side
    ``planner.goal_tolerance`` around ``goal``, nearest first (ties by position).

    Raises:
        NoPath: No free cell of that square is reachable (NavFn: no legal pose within
            tolerance, the planner server's NO_VALID_PATH).
        PlanningError: The start is invalid (as :meth:`GridPlanner.plan`).
    """
    grid = planner.grid
    tolerance = planner.goal_tolerance
    xs, ys = grid.cell_centres()
    cols = np.nonzero(np.abs(xs - goal[0]) <= tolerance)[0]
    rows = np.nonzero(np.abs(ys - goal[1]) <= tolerance)[0]
    cells = sorted((math.hypot(xs[c] - goal[0], ys[r] - goal[1]), int(r), int(c))
                   for r in rows for c in cols if not planner.blocked[r, c])
    for _, row, col in cells:
        try:
            return planner.plan(start, (float(xs[col]), float(ys[row])))
        except NoPath:
            continue
    raise NoPath(f"no path to ({goal[0]:.2f}, {goal[1]:.2f}): another robot covers it and "
                 f"no free cell within {tolerance} m (NavFn's tolerance) can be reached")


def plan_legs(planner: GridPlanner, robots: Sequence[Circle], start: Pose2D,
              poses: Sequence[Pose2D]) -> list[list[Point]]:
    """Plan from ``start`` through ``poses``; a pose another robot covers by :func:`approach`.

    Returns:
        One leg of waypoints per pose, each starting where the previous one ended.

    Raises:
        PlanningError: A leg cannot be planned.
    """
    legs: list[list[Point]] = []
    here = (start.x, start.y)
    for pose in poses:
        target = (pose.x, pose.y)
        leg = approach(planner, here, target) if covered(planner, robots, target) else \
            planner.plan(here, target)
        legs.append(leg)
        here = leg[-1]
    return legs


class Detour:
    """Replans a robot that another robot holds, at the global costmap's rate.

    Args:
        traffic: The other robots (the contact rule, :meth:`Traffic.hold`).
        costmaps: The costmaps whose planner sees the other robots.
    """

    def __init__(self, traffic: Traffic, costmaps: Costmaps) -> None:
        self._traffic = traffic
        self._costmaps = costmaps
        self._last_s = -math.inf

    def hold(self, goal: Goal | None, robot: DiffDrive, now_s: float, allowance_s: float
             ) -> tuple[bool, tuple[int, str] | None]:
        """:meth:`Traffic.hold`, and a new path for a held ``navigate_*`` goal if one exists.

        At most one replan per :data:`GLOBAL_UPDATE_S`; a given path (``follow_path``) is
        never replanned, as Nav2's controller follows the path it was given.
        """
        held, failure = self._traffic.hold(goal, robot.pose, now_s, allowance_s)
        if (held and failure is None and goal is not None and goal.kind is Kind.NAVIGATE
                and now_s - self._last_s >= GLOBAL_UPDATE_S):
            self._last_s = now_s
            self._replan(robot)
        return held, failure

    def _replan(self, robot: DiffDrive) -> None:
        end = robot.destination
        if end is None:
            return
        try:
            path = plan_legs(self._costmaps.planner(), self._costmaps.robots, robot.pose,
                             [end])[0]
        except PlanningError:
            return  # no way around: stand and wait, as before
        robot.follow(path, end.yaw)
