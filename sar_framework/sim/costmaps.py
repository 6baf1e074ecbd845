"""The two costmaps' phantom layer: obstacles that costmap clearing removes, walls that stay.

Plain Python (no ROS), thread-safe. Nav2's costmaps hold what the sensors marked; clearing
them drops those marks, never the static map. The simulator has no sensors, so the only marks
are the ``phantom_obstacles`` fault's circles, written into BOTH costmaps:

- the global costmap's phantoms are obstacles to the planner (:meth:`Costmaps.planner`:
  static map + ``blocked_areas`` + these), and to ``is_path_valid``;
- the local costmap's phantoms stop the controller (:meth:`Costmaps.local_blocks`: a path
  through one gives FollowPath's NO_VALID_CONTROL) and make drive_on_heading / backup see a
  collision ahead.

A fleet's other robots are a third layer of the global costmap only (:mod:`.traffic`), each
padded by the gap the controller keeps (:func:`~.traffic.padding`).

``blocked_areas`` are part of the base grid (a real wall): no clearing removes them.
Clearing follows Nav2's three services: entirely, around the robot (the phantoms whose centre
lies in the square of side ``reset_distance`` centred on the robot, as Nav2's
``clearLayerRegion``) and except that region (those outside it). A phantom is removed whole
or not at all, by its centre.
"""

from __future__ import annotations

import enum
import itertools
import threading
from collections.abc import Callable, Iterable, Sequence
from dataclasses import replace

from sar_framework.sim.faults import Circle, with_circles
from sar_framework.sim.geometry import segment_distance
from sar_framework.sim.goals import FOLLOW_PATH_NO_VALID_CONTROL
from sar_framework.sim.occupancy import OccupancyGrid
from sar_framework.sim.planner import GridPlanner
from sar_framework.sim.traffic import Traffic, padding

Point = tuple[float, float]


class Layer(enum.Enum):
    """Which costmap (Nav2's node names)."""

    GLOBAL = "global_costmap"
    LOCAL = "local_costmap"


def _in_square(circle: Circle, centre: Point, side: float) -> bool:
    """Whether ``circle``'s centre lies in the axis-aligned square of ``side`` at ``centre``."""
    return abs(circle.x - centre[0]) <= side / 2.0 and abs(circle.y - centre[1]) <= side / 2.0


class Costmaps:
    """The phantom obstacles of the global and local costmap over the map and its walls.

    Args:
        static: The map.
        robot_radius: Inflation radius of the planner, metres.
        phantoms: The phantoms written into both costmaps at start.
        walls: The ``blocked_areas`` (never cleared; :meth:`set_walls` replaces them).
        planner: The planner over ``static`` (no walls) if already built.
        traffic: The other robots of a fleet, an obstacle layer of the global costmap.
    """

    def __init__(self, static: OccupancyGrid, robot_radius: float,
                 phantoms: Iterable[Circle] = (), *, walls: Iterable[Circle] = (),
                 planner: GridPlanner | None = None, traffic: Traffic | None = None) -> None:
        self._static = static
        self._traffic = traffic
        self._radius = robot_radius
        self._lock = threading.Lock()
        self.walls = tuple(walls)
        self._base = with_circles(static, self.walls) if self.walls else static
        self._base_planner = planner if planner is not None and not self.walls else \
            GridPlanner(self._base, robot_radius=robot_radius)
        self._planner = self._base_planner
        self._phantoms: dict[Layer, tuple[Circle, ...]] = {layer: () for layer in Layer}
        self._planned: tuple[Circle, ...] = ()
        self.write(phantoms)

    @classmethod
    def over(cls, planner: GridPlanner) -> Costmaps:
        """Costmaps without phantoms over ``planner``'s grid and inflation."""
        return cls(planner.grid, planner.robot_radius, planner=planner)

    def set_walls(self, walls: Iterable[Circle]) -> None:
        """Replace the ``blocked_areas`` walls (tens of milliseconds: the planner is rebuilt)."""
        circles = tuple(walls)
        base = with_circles(self._static, circles) if circles else self._static
        planner = GridPlanner(base, robot_radius=self._radius)
        with self._lock:
            self.walls, self._base, self._base_planner = circles, base, planner
            self._planner, self._planned = planner, ()

    def phantoms(self, layer: Layer) -> tuple[Circle, ...]:
        """The phantoms ``layer`` holds now."""
        with self._lock:
            return self._phantoms[layer]

    def write(self, phantoms: Iterable[Circle]) -> None:
        """Write ``phantoms`` into both costmaps, replacing what they held."""
        circles = tuple(phantoms)
        with self._lock:
            for layer in Layer:
                self._phantoms[layer] = circles

    def clear(self, layer: Layer, keep: Callable[[Circle], bool] | None = None) -> int:
        """Remove the phantoms of ``layer`` that ``keep`` does not keep (all without it).

        Returns:
            How many were removed.
        """
        with self._lock:
            before = self._phantoms[layer]
            after = tuple(z for z in before if keep is not None and keep(z))
            self._phantoms[layer] = after
            return len(before) - len(after)

    def clear_around(self, layer: Layer, robot: Point, reset_distance: float) -> int:
        """ClearCostmapAroundRobot: remove the phantoms centred near the robot.

        Near: in the square of side ``reset_distance`` centred on ``robot`` (Nav2's
        ``clearLayerRegion``).
        """
        return self.clear(layer, lambda z: not _in_square(z, robot, reset_distance))

    def clear_except(self, layer: Layer, robot: Point, reset_distance: float) -> int:
        """ClearCostmapExceptRegion: remove the phantoms centred outside that square."""
        return self.clear(layer, lambda z: _in_square(z, robot, reset_distance))

    @property
    def robots(self) -> tuple[Circle, ...]:
        """The other robots as the global costmap holds them: padded by :func:`padding`."""
        if self._traffic is None:
            return ()
        pad = padding(self._static.resolution)
        return tuple(replace(z, radius=z.radius + pad) for z in self._traffic.in_costmap)

    def planner(self) -> GridPlanner:
        """The planner over the base grid plus the global costmap's phantoms and robots.

        Rebuilt (tens of milliseconds) only when those phantoms have changed.
        """
        others = self.robots
        with self._lock:
            circles = self._phantoms[Layer.GLOBAL] + others
            if circles == self._planned:
                return self._planner
            planner = self._base_planner if not circles else GridPlanner(
                with_circles(self._base, circles), robot_radius=self._radius)
            self._planner, self._planned = planner, circles
            return planner

    def local_failure(self, path: Sequence[Point]) -> tuple[int, str] | None:
        """FollowPath's NO_VALID_CONTROL if ``path`` runs through a local phantom, else None."""
        circle = self.local_blocks(path)
        if circle is None:
            return None
        return (FOLLOW_PATH_NO_VALID_CONTROL, "No valid trajectories: an obstacle of the "
                f"local costmap at ({circle.x:.2f}, {circle.y:.2f}) lies on the path")

    def local_blocks(self, path: Sequence[Point]) -> Circle | None:
        """The first local phantom the robot's footprint would touch along ``path``, if any."""
        with self._lock:
            circles = self._phantoms[Layer.LOCAL]
        if not circles or not path:
            return None
        segments = list(itertools.pairwise(path)) or [(path[0], path[0])]
        for circle in circles:
            reach = circle.radius + self._radius
            if any(segment_distance((circle.x, circle.y), a, b) < reach for a, b in segments):
                return circle
        return None
