"""The two costmaps' phantom layer: obstacles that costmap clearing removes, walls that stay.

Plain Python (no ROS), thread-safe. Nav2's costmaps hold what the sensors marked; clearing
them drops those marks, never the static map. The simulator has no sensors, so the only marks
are the ``phantom_obstacles`` fault's circles, written into BOTH costmaps:

- the global costmap's phantoms are obstacles to the planner (:meth:`Costmaps.planner`:
  static map + ``blocked_zones`` + these), and to ``is_path_valid``;
- the local costmap's phantoms stop the controller (:meth:`Costmaps.local_blocks`: a path
  through one gives FollowPath's NO_VALID_CONTROL) and make drive_on_heading / backup see a
  collision ahead.

``blocked_zones`` are part of the base grid (a real wall): no clearing removes them.
Clearing follows Nav2's three services: entirely, around the robot (phantoms whose centre is
within ``reset_distance`` of the robot) and except a region (those outside it).
"""

from __future__ import annotations

import enum
import itertools
import math
import threading
from collections.abc import Callable, Iterable, Sequence

from sar_framework.sim.faults import BlockedZone, with_blocked_zones
from sar_framework.sim.occupancy import OccupancyGrid
from sar_framework.sim.planner import GridPlanner

Point = tuple[float, float]


class Layer(enum.Enum):
    """Which costmap (Nav2's node names)."""

    GLOBAL = "global_costmap"
    LOCAL = "local_costmap"


def _segment_distance(p: Point, a: Point, b: Point) -> float:
    """Distance from ``p`` to segment ``a``-``b``."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    length_sq = dx * dx + dy * dy
    t = 0.0 if length_sq == 0.0 else ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / length_sq
    t = min(max(t, 0.0), 1.0)
    return math.hypot(p[0] - (a[0] + t * dx), p[1] - (a[1] + t * dy))


class Costmaps:
    """The phantom obstacles of the global and local costmap over one base grid.

    Args:
        base: The map with ``blocked_zones`` already added (never changes).
        robot_radius: Inflation radius of the planner, metres.
        phantoms: The phantoms written into both costmaps at start.
    """

    def __init__(self, base: OccupancyGrid, robot_radius: float,
                 phantoms: Iterable[BlockedZone] = ()) -> None:
        self._base = base
        self._radius = robot_radius
        self._lock = threading.Lock()
        self._base_planner = GridPlanner(base, robot_radius=robot_radius)
        self._planner = self._base_planner
        self._phantoms: dict[Layer, tuple[BlockedZone, ...]] = {layer: () for layer in Layer}
        self._planned: tuple[BlockedZone, ...] = ()
        self.write(phantoms)

    def phantoms(self, layer: Layer) -> tuple[BlockedZone, ...]:
        """The phantoms ``layer`` holds now."""
        with self._lock:
            return self._phantoms[layer]

    def write(self, phantoms: Iterable[BlockedZone]) -> None:
        """Write ``phantoms`` into both costmaps, replacing what they held."""
        zones = tuple(phantoms)
        with self._lock:
            for layer in Layer:
                self._phantoms[layer] = zones

    def clear(self, layer: Layer, keep: Callable[[BlockedZone], bool] | None = None) -> int:
        """Remove the phantoms of ``layer`` that ``keep`` does not keep (all without it).

        Returns:
            How many were removed.
        """
        with self._lock:
            before = self._phantoms[layer]
            after = tuple(z for z in before if keep is not None and keep(z))
            self._phantoms[layer] = after
            return len(before) - len(after)

    def clear_around(self, layer: Layer, robot: Point, distance: float) -> int:
        """ClearCostmapAroundRobot: remove phantoms centred within ``distance`` of ``robot``."""
        return self.clear(layer, lambda z: math.dist((z.x, z.y), robot) > distance)

    def clear_except(self, layer: Layer, robot: Point, distance: float) -> int:
        """ClearCostmapExceptRegion: remove phantoms centred farther than ``distance``."""
        return self.clear(layer, lambda z: math.dist((z.x, z.y), robot) <= distance)

    def planner(self) -> GridPlanner:
        """The planner over the base grid plus the global costmap's phantoms.

        Rebuilt (tens of milliseconds) only when those phantoms have changed.
        """
        with self._lock:
            zones = self._phantoms[Layer.GLOBAL]
            if zones == self._planned:
                return self._planner
            planner = self._base_planner if not zones else GridPlanner(
                with_blocked_zones(self._base, zones), robot_radius=self._radius)
            self._planner, self._planned = planner, zones
            return planner

    def local_blocks(self, path: Sequence[Point]) -> BlockedZone | None:
        """The first local phantom the robot's footprint would touch along ``path``, if any."""
        with self._lock:
            zones = self._phantoms[Layer.LOCAL]
        if not zones or not path:
            return None
        segments = list(itertools.pairwise(path)) or [(path[0], path[0])]
        for zone in zones:
            reach = zone.radius + self._radius
            if any(_segment_distance((zone.x, zone.y), a, b) < reach for a, b in segments):
                return zone
        return None
