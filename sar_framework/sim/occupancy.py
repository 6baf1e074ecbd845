"""Occupancy grids: rasterise a world, read nav2 map_server files, inflate obstacles.

Grid convention (as ``nav_msgs/OccupancyGrid``): ``data[row, col]`` with row 0 at the
map's *minimum* y, values ``FREE`` (0), ``OCCUPIED`` (100) and ``UNKNOWN`` (-1). The PGM
image is stored the other way up (row 0 = maximum y), as map_server expects.

The committed map is written by :mod:`sar_framework.sim.map_writer`.

Note on loading: with map_saver's ``free_thresh: 0.25`` map_server reads the unknown
shade 205 (occupancy 50/255 = 0.196) as *free*; :func:`load_map` follows map_server, so
cells outside the arena come back free. They are sealed off by the outer walls, so no
plan can reach them either way.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml
from PIL import Image

from sar_framework.sim.params import DEFAULT_MAP_YAML
from sar_framework.sim.world import Box, Cylinder, World

FREE = 0
OCCUPIED = 100
UNKNOWN = -1

PGM_FREE = 254
PGM_OCCUPIED = 0
PGM_UNKNOWN = 205

DEFAULT_RESOLUTION = 0.05
DEFAULT_MARGIN = 0.3
DEFAULT_MAP_PREFIX = DEFAULT_MAP_YAML.with_suffix("")
"""The simulator's default map without its extension (``maps/final_project_map``)."""
OCCUPIED_THRESH = 0.65
FREE_THRESH = 0.25

# An obstacle must overlap a cell by more than this (metres) to occupy it, so a wall face
# lying exactly on a cell edge does not spill into the neighbouring cell.
_OVERLAP_EPS = 1e-9


class MapError(ValueError):
    """A map yaml/image pair is missing or malformed; the message names file and key."""


@dataclass
class OccupancyGrid:
    """A 2-D occupancy grid in the ``map`` frame.

    Attributes:
        data: ``int8`` array ``(height, width)``; row 0 is the minimum y.
        resolution: Cell size, metres.
        origin_x: x of the lower-left corner of cell (0, 0), metres.
        origin_y: y of the lower-left corner of cell (0, 0), metres.
    """

    data: np.ndarray
    resolution: float
    origin_x: float
    origin_y: float

    @property
    def height(self) -> int:
        """Number of rows (cells along y)."""
        return int(self.data.shape[0])

    @property
    def width(self) -> int:
        """Number of columns (cells along x)."""
        return int(self.data.shape[1])

    def world_to_cell(self, x: float, y: float) -> tuple[int, int]:
        """Return the ``(row, col)`` containing point ``(x, y)``; may be out of bounds."""
        col = math.floor((x - self.origin_x) / self.resolution)
        row = math.floor((y - self.origin_y) / self.resolution)
        return row, col

    def cell_to_world(self, row: int, col: int) -> tuple[float, float]:
        """Return the ``(x, y)`` centre of cell ``(row, col)``."""
        return (
            self.origin_x + (col + 0.5) * self.resolution,
            self.origin_y + (row + 0.5) * self.resolution,
        )

    def in_bounds(self, row: int, col: int) -> bool:
        """Return True if ``(row, col)`` is a cell of the grid."""
        return 0 <= row < self.height and 0 <= col < self.width

    def value_at(self, x: float, y: float) -> int:
        """Return the cell value at ``(x, y)``, or ``UNKNOWN`` outside the grid."""
        row, col = self.world_to_cell(x, y)
        return int(self.data[row, col]) if self.in_bounds(row, col) else UNKNOWN

    def cell_centres(self) -> tuple[np.ndarray, np.ndarray]:
        """Return ``(xs, ys)``: 1-D arrays of the column and row centre coordinates."""
        xs = self.origin_x + (np.arange(self.width) + 0.5) * self.resolution
        ys = self.origin_y + (np.arange(self.height) + 0.5) * self.resolution
        return xs, ys


def _cell_window(
    grid: OccupancyGrid, bounds: tuple[float, float, float, float]
) -> tuple[slice, slice]:
    """Return the row/col slices of every cell that can touch the ``bounds`` rectangle."""
    min_x, min_y, max_x, max_y = bounds
    r0, c0 = grid.world_to_cell(min_x, min_y)
    r1, c1 = grid.world_to_cell(max_x, max_y)
    return (
        slice(max(r0, 0), min(r1 + 1, grid.height)),
        slice(max(c0, 0), min(c1 + 1, grid.width)),
    )


def _overlap_mask(
    obstacle: Box | Cylinder, xs: np.ndarray, ys: np.ndarray, half: float
) -> np.ndarray:
    """Return which square cells (centres ``xs`` x ``ys``, half-size ``half``) overlap ``obstacle``.

    Boxes use the separating axis theorem (two map axes, two box axes); cylinders compare
    the distance from the centre to the nearest point of each cell with the radius.
    """
    dx = xs[np.newaxis, :] - obstacle.x
    dy = ys[:, np.newaxis] - obstacle.y
    if isinstance(obstacle, Cylinder):
        nx = np.maximum(np.abs(dx) - half, 0.0)
        ny = np.maximum(np.abs(dy) - half, 0.0)
        return nx * nx + ny * ny < (obstacle.radius - _OVERLAP_EPS) ** 2
    c, s = abs(math.cos(obstacle.yaw)), abs(math.sin(obstacle.yaw))
    hl, hw = obstacle.length / 2.0, obstacle.width / 2.0
    u = dx * math.cos(obstacle.yaw) + dy * math.sin(obstacle.yaw)
    v = -dx * math.sin(obstacle.yaw) + dy * math.cos(obstacle.yaw)
    return (
        (np.abs(dx) < half + hl * c + hw * s - _OVERLAP_EPS)
        & (np.abs(dy) < half + hl * s + hw * c - _OVERLAP_EPS)
        & (np.abs(u) < hl + half * (c + s) - _OVERLAP_EPS)
        & (np.abs(v) < hw + half * (c + s) - _OVERLAP_EPS)
    )


def reachable(passable: np.ndarray, seed: tuple[int, int]) -> np.ndarray:
    """Return the cells 4-connected to ``seed`` through ``passable`` cells (numpy flood fill).

    Each round fills every row run and then every column run of passable cells that holds
    a reached cell, so a fill takes about as many rounds as the region's paths have turns,
    not as many as they have cells.

    Args:
        passable: Boolean mask of cells that may be crossed.
        seed: ``(row, col)`` to start from (must be in bounds).

    Returns:
        Boolean mask of the reached cells (all False when the seed is not passable).
    """
    reached = np.zeros_like(passable)
    if not passable[seed]:
        return reached
    reached[seed] = True
    row_runs, col_runs = _runs(passable), _runs(passable.T).T
    while True:
        grown = _fill_runs(_fill_runs(reached, row_runs), col_runs)
        if np.array_equal(grown, reached):
            return reached
        reached = grown


def _runs(passable: np.ndarray) -> np.ndarray:
    """Number each row's runs of consecutive passable cells (1, 2, ...; 0 = not passable)."""
    starts = passable.copy()
    starts[:, 1:] &= ~passable[:, :-1]
    return np.cumsum(starts, axis=None).reshape(passable.shape) * passable


def _fill_runs(reached: np.ndarray, runs: np.ndarray) -> np.ndarray:
    """Every cell of a run (numbered by :func:`_runs`) that holds a reached cell."""
    hit = np.zeros(int(runs.max()) + 1, dtype=bool)
    hit[runs[reached]] = True
    hit[0] = False
    return hit[runs]


def rasterize(
    world: World, resolution: float = DEFAULT_RESOLUTION, margin: float = DEFAULT_MARGIN
) -> OccupancyGrid:
    """Rasterise a world's obstacles into an occupancy grid, as a SLAM run would map it.

    A cell is ``OCCUPIED`` if any obstacle overlaps it, ``FREE`` if it is reachable from
    the robot's spawn cell (4-connected) without crossing an obstacle, and ``UNKNOWN``
    otherwise (outside the arena walls, pockets nobody could drive into).

    Args:
        world: The world.
        resolution: Cell size, metres.
        margin: Space added around the obstacles' bounding box, metres. The origin is
            snapped to a multiple of ``resolution`` so cell edges fall on round coordinates.

    Returns:
        The grid.
    """
    min_x, min_y, max_x, max_y = world.bounds()
    # round() before floor/ceil absorbs float noise such as -6.375 / 0.05 = -127.49999...
    col0 = math.floor(round((min_x - margin) / resolution, 6))
    row0 = math.floor(round((min_y - margin) / resolution, 6))
    width = math.ceil(round((max_x + margin) / resolution, 6)) - col0
    height = math.ceil(round((max_y + margin) / resolution, 6)) - row0
    grid = OccupancyGrid(
        data=np.full((height, width), UNKNOWN, dtype=np.int8),
        resolution=resolution,
        origin_x=round(col0 * resolution, 9),
        origin_y=round(row0 * resolution, 9),
    )
    xs, ys = grid.cell_centres()
    occupied = np.zeros((height, width), dtype=bool)
    for obstacle in world.obstacles:
        rows, cols = _cell_window(grid, obstacle.bounds())
        occupied[rows, cols] |= _overlap_mask(obstacle, xs[cols], ys[rows], resolution / 2.0)
    spawn = grid.world_to_cell(world.robot.spawn.x, world.robot.spawn.y)
    if grid.in_bounds(*spawn):
        grid.data[reachable(~occupied, spawn)] = FREE
    grid.data[occupied] = OCCUPIED
    return grid


def obstacle_distance(occupied: np.ndarray, resolution: float, max_distance: float) -> np.ndarray:
    """Distance from each cell centre to the nearest occupied cell centre, capped.

    Exact Euclidean distance up to ``max_distance``: each disk offset is applied as one
    shifted ``np.minimum`` over the whole grid, so the cost is (offsets x cells) in numpy.

    Args:
        occupied: Boolean mask of obstacle cells.
        resolution: Cell size, metres.
        max_distance: Cap, metres; farther cells get ``max_distance``.

    Returns:
        ``float32`` array of metres, 0 on occupied cells.
    """
    reach = math.floor(max_distance / resolution)
    # 0 on obstacles, +inf elsewhere: shifting it and adding the offset length gives the
    # distance via that offset, and a running minimum over all offsets gives the answer.
    seed = np.where(occupied, np.float32(0.0), np.float32(np.inf))
    dist = seed.copy()
    height, width = occupied.shape
    for dr in range(-reach, reach + 1):
        for dc in range(-reach, reach + 1):
            d = math.hypot(dr, dc) * resolution
            if (dr == 0 and dc == 0) or d > max_distance or abs(dr) >= height or abs(dc) >= width:
                continue
            # Cell (r, c) is within d of an obstacle at (r - dr, c - dc).
            src = seed[max(-dr, 0) : height - max(dr, 0), max(-dc, 0) : width - max(dc, 0)]
            dst = dist[max(dr, 0) : height + min(dr, 0), max(dc, 0) : width + min(dc, 0)]
            np.minimum(dst, src + np.float32(d), out=dst)
    np.minimum(dist, np.float32(max_distance), out=dist)
    return dist


def inflate(grid: OccupancyGrid, radius: float) -> np.ndarray:
    """Return the mask of cells whose centre lies within ``radius`` of an occupied cell centre.

    The mask includes the occupied cells themselves. With ``radius`` the robot's footprint
    radius, a robot centred on a cell outside the mask clears every obstacle cell centre.

    Args:
        grid: The grid (``OCCUPIED`` cells are the obstacles; unknown cells are not inflated).
        radius: Inflation radius, metres (e.g. 0.22 for the ROSbot).

    Returns:
        Boolean array shaped like ``grid.data``.
    """
    occupied = grid.data == OCCUPIED
    if radius <= 0.0:
        return occupied
    # Cap one cell beyond the radius (capped cells are then clearly outside), and compare
    # with a hair over the radius so a cell at exactly ``radius`` counts despite rounding.
    distance = obstacle_distance(occupied, grid.resolution, radius + grid.resolution)
    return distance <= radius + 1e-6


def spawn_problem(grid: OccupancyGrid, x: float, y: float) -> str | None:
    """Why a robot cannot start at ``(x, y)`` on ``grid`` (outside it, or not free), or None.

    Args:
        grid: The map.
        x: Metres, map frame.
        y: Metres, map frame.
    """
    row, col = grid.world_to_cell(x, y)
    if not grid.in_bounds(row, col):
        x1 = grid.origin_x + grid.width * grid.resolution
        y1 = grid.origin_y + grid.height * grid.resolution
        return (f"({x:g}, {y:g}) lies outside the map (x {grid.origin_x:g}..{x1:g}, "
                f"y {grid.origin_y:g}..{y1:g})")
    value = int(grid.data[row, col])
    if value != FREE:
        what = {OCCUPIED: "occupied", UNKNOWN: "unknown"}.get(value, f"occupancy {value}")
        return f"({x:g}, {y:g}) is not free on the map ({what})"
    return None


def _yaml_number(doc: dict, key: str, source: str) -> float:
    value = doc.get(key)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise MapError(f"{source}: {key}: expected a finite number, got {value!r}")
    return float(value)


def load_map(yaml_path: str | Path) -> OccupancyGrid:
    """Read a map_server yaml + image pair into a grid, interpreting pixels as map_server does.

    Supports ``mode`` trinary (default), scale and raw, and ``negate``. Occupancy of a pixel
    is ``1 - shade/255`` (``shade/255`` when negated); above ``occupied_thresh`` is
    ``OCCUPIED``, below ``free_thresh`` is ``FREE``; in scale mode, between them is graded
    0..100 and a pixel not fully opaque (an image with alpha) is ``UNKNOWN``.

    Args:
        yaml_path: The map's yaml file; ``image`` is resolved relative to it.

    Returns:
        The grid, row 0 at the minimum y.

    Raises:
        MapError: If a file is missing or a key is missing or malformed.
    """
    source = str(yaml_path)
    try:
        doc = yaml.safe_load(Path(yaml_path).read_text(encoding="utf-8"))
    except OSError as exc:
        raise MapError(f"{source}: cannot read map yaml: {exc.strerror or exc}") from exc
    except yaml.YAMLError as exc:
        raise MapError(f"{source}: invalid YAML: {exc}") from exc
    if not isinstance(doc, dict):
        raise MapError(f"{source}: expected a mapping at the top level")
    for key in ("image", "resolution", "origin"):
        if key not in doc:
            raise MapError(f"{source}: {key}: missing key")
    if not isinstance(doc["image"], str) or not doc["image"]:
        raise MapError(f"{source}: image: expected a file name, got {doc['image']!r}")
    resolution = _yaml_number(doc, "resolution", source)
    if resolution <= 0.0:
        raise MapError(f"{source}: resolution: expected a positive number, got {resolution!r}")
    origin = doc["origin"]
    if (
        not isinstance(origin, list)
        or len(origin) != 3
        or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in origin)
    ):
        raise MapError(f"{source}: origin: expected [x, y, yaw] numbers, got {origin!r}")
    mode = doc.get("mode", "trinary")
    if mode not in ("trinary", "scale", "raw"):
        raise MapError(f"{source}: mode: expected trinary, scale or raw, got {mode!r}")
    occupied_thresh = _yaml_number({"occupied_thresh": 0.65, **doc}, "occupied_thresh", source)
    free_thresh = _yaml_number({"free_thresh": 0.25, **doc}, "free_thresh", source)
    for key, value in (("occupied_thresh", occupied_thresh), ("free_thresh", free_thresh)):
        if not 0.0 <= value <= 1.0:
            raise MapError(f"{source}: {key}: expected a number from 0 to 1, got {value!r}")
    if free_thresh >= occupied_thresh:
        raise MapError(f"{source}: free_thresh: expected below occupied_thresh "
                       f"({occupied_thresh!r}), got {free_thresh!r}")
    negate = doc.get("negate", 0)
    if negate not in (0, 1):
        raise MapError(f"{source}: negate: expected 0 or 1, got {negate!r}")

    image_path = Path(yaml_path).parent / doc["image"]
    try:
        with Image.open(image_path) as image:
            shade = np.asarray(image.convert("L"), dtype=np.float64)
            opaque = (np.asarray(image.getchannel("A")) == 255 if "A" in image.getbands()
                      else np.ones(shade.shape, dtype=bool))
    except (OSError, ValueError) as exc:
        raise MapError(f"{source}: image: cannot read {image_path}: {exc}") from exc

    shade, opaque = np.flipud(shade), np.flipud(opaque)
    data = np.full(shade.shape, UNKNOWN, dtype=np.int8)
    if mode == "raw":
        in_range = shade <= OCCUPIED
        data[in_range] = shade[in_range].astype(np.int8)
    else:
        occ = shade / 255.0 if negate else 1.0 - shade / 255.0
        if mode == "scale":
            ratio = (occ - free_thresh) / (occupied_thresh - free_thresh)
            data[:] = np.rint(np.clip(ratio, 0.0, 1.0) * 100.0).astype(np.int8)
        data[occ > occupied_thresh] = OCCUPIED
        data[occ < free_thresh] = FREE
        if mode == "scale":
            data[~opaque] = UNKNOWN  # map_server: a transparent pixel is unknown in scale mode
    return OccupancyGrid(
        data=data, resolution=resolution, origin_x=float(origin[0]), origin_y=float(origin[1])
    )
