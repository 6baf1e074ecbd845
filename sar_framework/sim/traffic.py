"""Other robots as obstacles, for one robot of a fleet (plain Python).

Each robot's :class:`Traffic` holds the other robots' footprints (circles). Two readers:

- the **global costmap** (:class:`~.costmaps.Costmaps`) takes a snapshot as an obstacle
  layer at Nav2's global costmap ``update_frequency`` (1 Hz simulated,
  config/nav2_params.yaml), so the planner routes around the robots where they were at
  the last update, or fails (NO_VALID_PATH) when one stands in the only way;
- the **controller** (:meth:`Traffic.ahead`) sees them live: a robot does not drive into
  another robot's footprint. It stands still while one is in its way ahead, and its goal
  fails after ``movement_time_allowance`` with FollowPath's FAILED_TO_MAKE_PROGRESS, as
  Nav2's progress checker fails a controller blocked by an obstacle.

A single robot's :class:`Traffic` stays empty: nothing changes for it.
"""

from __future__ import annotations

import math
import threading
from collections.abc import Sequence

from sar_framework.sim.faults import Circle
from sar_framework.sim.goals import FOLLOW_PATH_NO_PROGRESS, Goal, Kind
from sar_framework.sim.world import Pose2D

__all__ = ["CLEARANCE_M", "GLOBAL_UPDATE_S", "Traffic", "padding"]

CLEARANCE_M = 0.05
"""Gap the controller keeps between two footprints, metres."""

GLOBAL_UPDATE_S = 1.0
"""Simulated seconds between global costmap updates of the other robots (Nav2's 1 Hz)."""


def padding(resolution: float) -> float:
    """How much wider than its footprint another robot enters the global costmap, metres.

    :data:`CLEARANCE_M` (the gap the controller keeps) plus 1.5 cell diagonals for the
    raster, so the planner and the contact rule agree. A cell is free when its centre is
    more than this robot's radius ``r`` from every occupied cell centre; the occupied cells
    cover the padded circle ``R`` to within half a diagonal, so a free cell's centre is more
    than ``R + r - diagonal`` from the other robot's centre, and a path through free cells
    passes no closer than ``R + r - 1.5 diagonals``: with this padding, at least both radii
    plus :data:`CLEARANCE_M`, where the controller would stop it.
    """
    return CLEARANCE_M + 1.5 * math.sqrt(2.0) * resolution


class Traffic:
    """The other robots of one robot's fleet, live and as the global costmap last saw them.

    Args:
        radius: This robot's footprint radius, metres.
    """

    def __init__(self, radius: float) -> None:
        self.radius = radius
        self._lock = threading.Lock()
        self._live: tuple[Circle, ...] = ()
        self._costmap: tuple[Circle, ...] = ()
        self._next_update_s = 0.0
        self._blocked_since: float | None = None

    def update(self, others: Sequence[Circle], now_s: float) -> None:
        """The other robots' footprints now (called by the physics loop every step)."""
        with self._lock:
            self._live = tuple(others)
            if now_s >= self._next_update_s:
                self._costmap = self._live
                self._next_update_s = now_s + GLOBAL_UPDATE_S

    def refresh(self) -> None:
        """Make the global costmap see the robots as they are now (a reset)."""
        with self._lock:
            self._costmap = self._live

    @property
    def in_costmap(self) -> tuple[Circle, ...]:
        """The other robots as the global costmap holds them."""
        with self._lock:
            return self._costmap

    def ahead(self, pose: Pose2D) -> Circle | None:
        """The robot whose footprint a forward move from ``pose`` would touch, if any.

        A robot in contact (within both radii plus :data:`CLEARANCE_M`) and in front (less
        than 90 degrees off the heading) blocks; one beside or behind does not, so two
        robots that touch can still part.
        """
        with self._lock:
            others = self._live
        for circle in others:
            dx, dy = circle.x - pose.x, circle.y - pose.y
            if math.hypot(dx, dy) >= circle.radius + self.radius + CLEARANCE_M:
                continue
            if dx * math.cos(pose.yaw) + dy * math.sin(pose.yaw) > 0.0:
                return circle
        return None

    def hold(self, goal: Goal | None, pose: Pose2D, now_s: float, allowance_s: float
             ) -> tuple[bool, tuple[int, str] | None]:
        """Whether the robot at ``pose`` must stand still now, and ``goal``'s failure if due.

        Args:
            goal: The running goal; only a path (``navigate_*``, ``follow_path``) is held,
                and any other goal, or none, forgets a block.
            pose: The robot's pose.
            now_s: Simulated time.
            allowance_s: The progress checker's ``movement_time_allowance``.

        Returns:
            ``(hold, failure)``: failure is FAILED_TO_MAKE_PROGRESS once the robot has been
            held ``allowance_s`` seconds in a row, else None.
        """
        drives = goal is not None and goal.active and goal.kind in (Kind.NAVIGATE, Kind.FOLLOW)
        circle = self.ahead(pose) if drives else None
        if circle is None:
            self._blocked_since = None
            return False, None
        if self._blocked_since is None:
            self._blocked_since = now_s
        if now_s - self._blocked_since < allowance_s:
            return True, None
        self._blocked_since = None
        return True, (FOLLOW_PATH_NO_PROGRESS, "Failed to make progress: another robot at "
                      f"({circle.x:.2f}, {circle.y:.2f}) blocks the way for {allowance_s:g} s")
