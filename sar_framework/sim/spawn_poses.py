"""Spawn poses for N robots near the base station, and the fleet file that holds them.

Plain Python (numpy, no ROS). ``sar-tree run --robots N`` and ``fleet.launch.py robots:=N``
write a fleet file (:mod:`.fleet_file`) from :func:`spawn_poses`. The places are points
of a lattice of :data:`SPACING_M` between :data:`MIN_BASE_DISTANCE_M` and
:data:`SEARCH_RADIUS_M` from the base station, each clear of walls and debris by the
footprint plus :data:`CLEARANCE_MARGIN_M`, reachable from the base, and at least
:data:`TRAFFIC_CLEARANCE_M` from the paths the simulator's planner plans between the base
and the mission's destinations (a robot at home is in nobody's way). The first is the
nearest; each next one the place farthest from those chosen (so the robots spread over
the rooms around the base), at least :data:`SPACING_M` from all of them: well over the
simulator's two footprints, so no robot starts blocked.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from sar_framework.sim.occupancy import OccupancyGrid, inflate, reachable
from sar_framework.sim.world import Pose2D

__all__ = ["CLEARANCE_MARGIN_M", "MAX_ROBOTS", "SPACING_M", "SpawnError", "fleet_text",
           "spawn_poses", "write_fleet_file"]

SPACING_M = 1.0
"""Metres between two spawn poses (and the lattice step)."""
CLEARANCE_MARGIN_M = 0.5
"""Metres of free space beyond the footprint around a spawn pose: away from walls, so no
robot waiting at home stands in a doorway's approach."""
MAX_ROBOTS = 8
"""The most robots ``--robots`` accepts."""
SEARCH_RADIUS_M = 4.5
"""How far from the base spawn poses are looked for."""
MIN_BASE_DISTANCE_M = 2.0
"""How near the base a spawn may be: the example's base is the hub every path crosses, so
robots waiting at home keep clear of it."""
TRAFFIC_CLEARANCE_M = 1.0
"""How near a planned path between the base and a destination a spawn may be (two footprints
and a margin: the simulator stops a robot in contact with another ahead)."""


class SpawnError(ValueError):
    """Not enough free places near the base for the robots asked for."""


def _traffic(base: tuple[float, float], places: Sequence[tuple[float, float]],
             grid: OccupancyGrid, radius: float) -> list[tuple[float, float]]:
    """Points, 0.1 m apart, of the planned paths between the base and the places."""
    from sar_framework.sim.planner import GridPlanner, PlanningError

    planner = GridPlanner(grid, radius)
    ends = [base, *places]
    points: list[tuple[float, float]] = []
    for i, a in enumerate(ends):
        for b in ends[i + 1:]:
            try:
                path = planner.plan(a, b)
            except PlanningError:
                continue
            for (x0, y0), (x1, y1) in itertools.pairwise(path):
                steps = max(1, math.ceil(math.dist((x0, y0), (x1, y1)) / 0.1))
                points += [(x0 + (x1 - x0) * k / steps, y0 + (y1 - y0) * k / steps)
                           for k in range(steps + 1)]
    return points


def spawn_poses(count: int, base: tuple[float, float], grid: OccupancyGrid, radius: float,
                spacing: float = SPACING_M, *,
                destinations: Sequence[tuple[float, float]] = ()) -> list[Pose2D]:
    """``count`` spawn poses in free space near ``base``, spread out (see the module).

    Args:
        count: How many robots.
        base: The base station ``(x, y)``, metres.
        grid: The map the robots drive in.
        radius: The robots' footprint radius, metres.
        spacing: Metres between two poses.
        destinations: Where the mission sends the robots: no pose within
            :data:`TRAFFIC_CLEARANCE_M` of the planned paths between the base and them
            (robots waiting at home are out of the others' way).

    Returns:
        The poses (yaw 0), in the order chosen.

    Raises:
        SpawnError: Fewer than ``count`` places.
    """
    blocked = inflate(grid, radius + CLEARANCE_MARGIN_M) | (grid.data != 0)
    base_cell = grid.world_to_cell(*base)
    if not grid.in_bounds(*base_cell):
        raise SpawnError(f"the base station ({base[0]:g}, {base[1]:g}) is outside the map")
    passable = ~inflate(grid, radius)
    around = reachable(passable, _nearest(passable, base_cell))  # where the base's robots go
    steps = int(SEARCH_RADIUS_M / spacing)
    lattice = ((base[0] + i * spacing, base[1] + j * spacing)
               for i in range(-steps, steps + 1) for j in range(-steps, steps + 1))
    traffic = np.array(_traffic(base, destinations, grid, radius) or [(math.inf, math.inf)])
    places = []
    for x, y in lattice:
        if np.min(np.hypot(traffic[:, 0] - x, traffic[:, 1] - y)) < TRAFFIC_CLEARANCE_M:
            continue
        cell = grid.world_to_cell(x, y)
        if MIN_BASE_DISTANCE_M <= math.dist((x, y), base) <= SEARCH_RADIUS_M \
                and grid.in_bounds(*cell) and not blocked[cell] and around[cell]:
            places.append((x, y))
    places.sort(key=lambda p: (round(math.dist(p, base), 6),
                               math.atan2(p[1] - base[1], p[0] - base[0])))
    chosen: list[tuple[float, float]] = places[:1]
    while chosen and len(chosen) < count:
        gaps = [(min(math.dist(p, c) for c in chosen), -i) for i, p in enumerate(places)]
        gap, index = max(gaps)
        if gap < spacing - 1e-9:
            break
        chosen.append(places[-index])
    if len(chosen) == count:
        return [Pose2D(round(x, 3), round(y, 3), 0.0) for x, y in chosen]
    raise SpawnError(f"only {len(chosen)} free spawn places {MIN_BASE_DISTANCE_M:g} to "
                     f"{SEARCH_RADIUS_M:g} m from the base station, {count} robots asked for")


def _nearest(mask: np.ndarray, cell: tuple[int, int]) -> tuple[int, int]:
    """The cell of ``mask`` nearest to ``cell`` (``cell`` itself when set or none is)."""
    rows, cols = np.nonzero(mask)
    if mask[cell] or not len(rows):
        return cell
    best = int(np.argmin((rows - cell[0]) ** 2 + (cols - cell[1]) ** 2))
    return int(rows[best]), int(cols[best])


def fleet_text(poses: Sequence[Pose2D], prefix: str = "robot") -> str:
    """The fleet file for ``poses``: robots ``robot1``, ``robot2``... in order."""
    lines = ["# written by sar-tree run --robots / fleet.launch.py robots:=N", "robots:"]
    for number, pose in enumerate(poses, start=1):
        lines += [f"  - name: {prefix}{number}",
                  f"    pose: {{x: {pose.x:g}, y: {pose.y:g}, yaw: {pose.yaw:g}}}"]
    return "\n".join(lines) + "\n"


def write_fleet_file(path: str | Path, count: int, base: tuple[float, float],
                     grid: OccupancyGrid, radius: float, *,
                     destinations: Sequence[tuple[float, float]] = ()) -> Path:
    """Write the fleet file of ``count`` robots near ``base`` to ``path`` and return it.

    Raises:
        SpawnError: Not enough free places.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    poses = spawn_poses(count, base, grid, radius, destinations=destinations)
    path.write_text(fleet_text(poses), encoding="utf-8")
    return path


def free_places(grid: OccupancyGrid, radius: float) -> np.ndarray:
    """The cells a robot of ``radius`` can stand on (for tests and figures)."""
    return ~(inflate(grid, radius) | (grid.data != 0))
