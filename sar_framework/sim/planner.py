"""Grid path planner: A* over the inflated occupancy grid, then line-of-sight shortcuts.

Usage::

    planner = GridPlanner(load_map("maps/final_project_map.yaml"), robot_radius=0.22)
    waypoints = planner.plan((0.0, 0.0), (-3.0, 3.0))   # [(x, y), ...] in metres

Cells within ``robot_radius`` of an obstacle (and unknown cells) are *blocked*. The search
is 8-connected without cutting blocked corners, with the octile distance as heuristic and a
step cost that grows near obstacles so paths keep some clearance where there is room.
The cell path is then reduced to the waypoints where a straight segment would first touch
a blocked cell (exact cell traversal), so it is not staircase-shaped.

A start inside the blocked band (the robot hugging a wall) escapes to the nearest free
cell; a goal inside it is approached from the nearest free cell within ``goal_tolerance``
and then reached straight. Both short legs avoid occupied cells. Failures raise a
:class:`PlanningError` subclass.
"""

from __future__ import annotations

import heapq
import math

import numpy as np

from sar_framework.sim.occupancy import (
    OCCUPIED,
    UNKNOWN,
    OccupancyGrid,
    obstacle_distance,
    reachable,
)

Point = tuple[float, float]

_SQRT2 = math.sqrt(2.0)
# Scaling the heuristic up by 0.1 % breaks ties between equal-f cells towards the goal,
# which saves most expansions in open rooms; paths stay within 0.1 % of optimal.
_TIE_BREAK = 1.001


class PlanningError(RuntimeError):
    """No plan could be made; subclasses say why.

    ``error_code`` is Jazzy's ``nav2_msgs/action/ComputePathToPose`` result code for it.
    """

    error_code = 200  # UNKNOWN


class StartInObstacle(PlanningError):  # noqa: N818 - the names are the API
    """The start is inside an obstacle, or boxed in by inflation."""

    error_code = 205  # START_OCCUPIED


class GoalInObstacle(PlanningError):  # noqa: N818 - the names are the API
    """The goal is inside an obstacle, or too close to one to reach."""

    error_code = 206  # GOAL_OCCUPIED


class StartOutsideMap(StartInObstacle):
    """The start is outside the map."""

    error_code = 203  # START_OUTSIDE_MAP


class GoalOutsideMap(GoalInObstacle):
    """The goal is outside the map."""

    error_code = 204  # GOAL_OUTSIDE_MAP


class NoPath(PlanningError):  # noqa: N818 - the names are the API
    """Start and goal are both valid but not connected through free space."""

    error_code = 208  # NO_VALID_PATH


class GridPlanner:
    """A* planner over an occupancy grid inflated by the robot's radius.

    Construction precomputes the blocked mask, the cost field and the connected regions
    (tens of milliseconds); :meth:`plan` is then cheap enough to call per goal.

    Args:
        grid: The map (``OCCUPIED`` and ``UNKNOWN`` cells are obstacles).
        robot_radius: Inflation radius, metres.
        clearance: Preferred distance, metres, from obstacles. Cells closer than this
            (but outside the inflation) cost more to cross, rising linearly towards the
            inflation, and shortcuts between points that both keep this clearance must
            keep it too.
        clearance_weight: Extra cost factor at the edge of the inflation (0 disables the
            cost; the shortcut rule still applies).
        escape_radius: How far, metres, a blocked start may be moved to a free cell.
        goal_tolerance: How far, metres, the free approach cell of a goal that lies in the
            inflation may be from it.
    """

    def __init__(
        self,
        grid: OccupancyGrid,
        robot_radius: float = 0.22,
        *,
        clearance: float = 0.4,
        clearance_weight: float = 0.5,
        escape_radius: float = 1.0,
        goal_tolerance: float = 0.5,
    ) -> None:
        self.grid = grid
        self.robot_radius = robot_radius
        self.escape_radius = escape_radius
        self.goal_tolerance = goal_tolerance
        res = grid.resolution
        self.lethal: np.ndarray = (grid.data == OCCUPIED) | (grid.data == UNKNOWN)
        """Cells the robot's centre must never enter (obstacles and unknown)."""
        cap = max(clearance, robot_radius + res)
        distance = obstacle_distance(grid.data == OCCUPIED, res, cap)
        self.blocked: np.ndarray = self.lethal | (distance <= robot_radius + 1e-6)
        """Cells the planned path avoids: lethal cells plus the inflation band."""
        self._cramped = self.blocked | (distance < cap - 1e-6)

        # Step cost multiplier, >= 1 so the octile heuristic stays admissible.
        band = max(cap - robot_radius, 1e-9)
        closeness = np.clip((cap - distance) / band, 0.0, 1.0)
        multiplier = 1.0 + clearance_weight * closeness

        # Flat arrays with a one-cell blocked border: neighbours never need bounds checks.
        height, width = self.blocked.shape
        self._stride = width + 2
        padded = np.ones((height + 2, width + 2), dtype=bool)
        padded[1:-1, 1:-1] = self.blocked
        self._blocked_flat: list[bool] = padded.ravel().tolist()
        padded_cost = np.ones((height + 2, width + 2))
        padded_cost[1:-1, 1:-1] = multiplier
        self._cost_flat: list[float] = padded_cost.ravel().tolist()
        rows, cols = np.indices(padded.shape)
        self._rows, self._cols = rows.ravel(), cols.ravel()
        self._regions = self._label_regions(~self.blocked)

    @staticmethod
    def _label_regions(free: np.ndarray) -> np.ndarray:
        """Label the 4-connected free regions (1, 2, ...; 0 = blocked) to reject NoPath fast."""
        labels = np.zeros(free.shape, dtype=np.int32)
        remaining = free.copy()
        label = 0
        while remaining.any():
            label += 1
            seed = np.unravel_index(int(np.argmax(remaining)), free.shape)
            region = reachable(remaining, (int(seed[0]), int(seed[1])))
            labels[region] = label
            remaining &= ~region
        return labels

    # ----------------------------------------------------------------- queries

    def is_free(self, x: float, y: float) -> bool:
        """Return True if a path may pass through ``(x, y)`` (in the map, not blocked)."""
        row, col = self.grid.world_to_cell(x, y)
        return self.grid.in_bounds(row, col) and not self.blocked[row, col]

    def is_lethal(self, x: float, y: float) -> bool:
        """Return True if ``(x, y)`` is outside the map or in an occupied or unknown cell."""
        row, col = self.grid.world_to_cell(x, y)
        return not self.grid.in_bounds(row, col) or bool(self.lethal[row, col])

    def segment_is_clear(self, a: Point, b: Point, *, mask: np.ndarray | None = None) -> bool:
        """Return True if segment ``a``-``b`` (metres) touches no cell of ``mask``.

        Args:
            a: Segment start, metres.
            b: Segment end, metres.
            mask: Cells to avoid (default: :attr:`blocked`); outside the map counts as hit.
        """
        return self._clear(
            self._to_grid(a), self._to_grid(b), self.blocked if mask is None else mask
        )

    def plan(self, start: Point, goal: Point) -> list[Point]:
        """Plan from ``start`` to ``goal`` (metres, map frame).

        Args:
            start: Robot position.
            goal: Target position.

        Returns:
            Waypoints in metres, the first exactly ``start`` and the last exactly ``goal``;
            consecutive waypoints are joined by straight, collision-free segments.

        Raises:
            StartInObstacle: Start outside the map, in an occupied cell, or no free cell
                within ``escape_radius``.
            GoalInObstacle: Goal outside the map, in an occupied cell, or no free cell
                within ``goal_tolerance``.
            NoPath: Start and goal are in disconnected free regions.
        """
        s_uv, g_uv = self._to_grid(start), self._to_grid(goal)
        s_cell = self._cell_of(s_uv)
        g_cell = self._cell_of(g_uv)
        if not self._inside(s_cell):
            raise StartOutsideMap(f"start ({start[0]:.2f}, {start[1]:.2f}) is outside the map")
        if not self._inside(g_cell):
            raise GoalOutsideMap(f"goal ({goal[0]:.2f}, {goal[1]:.2f}) is outside the map")
        if self.lethal[s_cell]:
            raise StartInObstacle(f"start ({start[0]:.2f}, {start[1]:.2f}) is inside an obstacle")
        if self.lethal[g_cell]:
            raise GoalInObstacle(f"goal ({goal[0]:.2f}, {goal[1]:.2f}) is inside an obstacle")

        first = s_cell
        if self.blocked[s_cell]:
            first = self._nearest_free(s_uv, self.escape_radius)
            if first is None:
                raise StartInObstacle(
                    f"start ({start[0]:.2f}, {start[1]:.2f}) is within {self.robot_radius} m of "
                    f"an obstacle and no free cell is within {self.escape_radius} m"
                )
        last = g_cell
        if self.blocked[g_cell]:
            last = self._nearest_free(g_uv, self.goal_tolerance)
            if last is None:
                raise GoalInObstacle(
                    f"goal ({goal[0]:.2f}, {goal[1]:.2f}) is within {self.robot_radius} m of "
                    f"an obstacle and no free cell is within {self.goal_tolerance} m"
                )
        if self._regions[first] != self._regions[last]:
            raise NoPath(
                f"no path from ({start[0]:.2f}, {start[1]:.2f}) to ({goal[0]:.2f}, {goal[1]:.2f}):"
                " they are in separate free regions"
            )

        cells = self._astar(first, last)
        if len(cells) == 1:  # same cell: still a start and an end point
            cells.append(cells[0])
        points = [(c + 0.5, r + 0.5) for r, c in cells]
        # Keep the exact endpoints when they are free (same cell as the search endpoints).
        if first == s_cell:
            points[0] = s_uv
        if last == g_cell:
            points[-1] = g_uv
        points = self._shortcut(points)
        if first != s_cell:
            points.insert(0, s_uv)
        if last != g_cell:
            points.append(g_uv)
        return [self._to_world(p) for p in points]

    # ----------------------------------------------------------------- internals

    def _to_grid(self, p: Point) -> Point:
        """Metres -> grid coordinates ``(u, v)``; cell (r, c) spans [c, c+1) x [r, r+1)."""
        g = self.grid
        return ((p[0] - g.origin_x) / g.resolution, (p[1] - g.origin_y) / g.resolution)

    def _to_world(self, uv: Point) -> Point:
        g = self.grid
        return (g.origin_x + uv[0] * g.resolution, g.origin_y + uv[1] * g.resolution)

    @staticmethod
    def _cell_of(uv: Point) -> tuple[int, int]:
        return math.floor(uv[1]), math.floor(uv[0])

    def _inside(self, cell: tuple[int, int]) -> bool:
        return self.grid.in_bounds(*cell)

    def _nearest_free(self, uv: Point, radius: float) -> tuple[int, int] | None:
        """Nearest free cell within ``radius`` metres with a straight leg clear of lethal cells."""
        reach = math.ceil(radius / self.grid.resolution)
        row, col = self._cell_of(uv)
        r0, c0 = max(row - reach, 0), max(col - reach, 0)
        window = self.blocked[r0 : row + reach + 1, c0 : col + reach + 1]
        rows, cols = np.nonzero(~window)
        if rows.size == 0:
            return None
        rows, cols = rows + r0, cols + c0
        dist = np.hypot(cols + 0.5 - uv[0], rows + 0.5 - uv[1]) * self.grid.resolution
        order = np.lexsort((cols, rows, dist))  # by distance, ties broken by position
        for i in order:
            if dist[i] > radius:
                break
            cell = (int(rows[i]), int(cols[i]))
            if self._clear(uv, (cell[1] + 0.5, cell[0] + 0.5), self.lethal):
                return cell
        return None

    def _astar(self, first: tuple[int, int], last: tuple[int, int]) -> list[tuple[int, int]]:
        """A* between two free cells of the same region; returns the cell sequence."""
        stride = self._stride
        start = (first[0] + 1) * stride + first[1] + 1
        goal = (last[0] + 1) * stride + last[1] + 1
        blocked = self._blocked_flat
        cost = self._cost_flat
        # Octile distance to the goal for every cell at once (numpy), then plain lists:
        # list indexing is what the inner loop does fastest.
        dr = np.abs(self._rows - (last[0] + 1))
        dc = np.abs(self._cols - (last[1] + 1))
        heuristic = (_TIE_BREAK * (dr + dc + (_SQRT2 - 2.0) * np.minimum(dr, dc))).tolist()

        # (offset, step length, the two orthogonal offsets a diagonal must not cut through)
        moves = [(1, 1.0, 0, 0), (-1, 1.0, 0, 0), (stride, 1.0, 0, 0), (-stride, 1.0, 0, 0)]
        moves += [(r + c, _SQRT2, r, c) for r in (stride, -stride) for c in (1, -1)]
        size = len(blocked)
        g_score = [math.inf] * size
        parent = [-1] * size
        closed = bytearray(size)
        g_score[start] = 0.0
        frontier = [(heuristic[start], start)]
        pop, push = heapq.heappop, heapq.heappush
        while frontier:
            current = pop(frontier)[1]
            if current == goal:
                break
            if closed[current]:
                continue
            closed[current] = 1
            g_current = g_score[current]
            for offset, length, ortho_a, ortho_b in moves:
                nxt = current + offset
                if blocked[nxt] or closed[nxt]:
                    continue
                if ortho_a and (blocked[current + ortho_a] or blocked[current + ortho_b]):
                    continue
                g_next = g_current + length * cost[nxt]
                if g_next < g_score[nxt]:
                    g_score[nxt] = g_next
                    parent[nxt] = current
                    push(frontier, (g_next + heuristic[nxt], nxt))
        else:  # pragma: no cover - regions were checked, so the goal is always reached
            raise NoPath("search exhausted the free region without reaching the goal")
        path = [goal]
        while path[-1] != start:
            path.append(parent[path[-1]])
        path.reverse()
        return [(i // stride - 1, i % stride - 1) for i in path]

    def _shortcut(self, points: list[Point]) -> list[Point]:
        """Reduce a dense point path to the waypoints where straight segments must bend.

        From each kept point, binary-search the farthest later point that is visible
        and keep it. A segment between two points that both keep the preferred clearance
        must keep it all along; otherwise it must only avoid blocked cells. Visibility
        along a path is not strictly monotonic, so the search may keep a waypoint more
        than needed, never an unsafe one: every kept segment is checked, and neighbouring
        path points are always visible.
        """
        roomy = [not self._cramped[self._cell_of(p)] for p in points]

        def visible(i: int, j: int) -> bool:
            mask = self._cramped if roomy[i] and roomy[j] else self.blocked
            return self._clear(points[i], points[j], mask)

        kept = [points[0]]
        anchor, last = 0, len(points) - 1
        while anchor < last:
            if visible(anchor, last):
                best = last
            else:
                best, lo, hi = anchor + 1, anchor + 2, last - 1
                while lo <= hi:
                    mid = (lo + hi) // 2
                    if visible(anchor, mid):
                        best, lo = mid, mid + 1
                    else:
                        hi = mid - 1
            kept.append(points[best])
            anchor = best
        return kept

    def _clear(self, a: Point, b: Point, mask: np.ndarray) -> bool:
        """Exact test: does segment ``a``-``b`` (grid coordinates) avoid every cell of ``mask``?

        The segment is cut where it crosses grid lines; the midpoint of each piece lies
        inside exactly one traversed cell, so every cell the segment passes through is
        checked (touching a cell only at a corner does not count).
        """
        (u0, v0), (u1, v1) = a, b
        ts = [np.array([0.0, 1.0])]
        for p0, p1 in ((u0, u1), (v0, v1)):
            if p1 != p0:
                lines = np.arange(math.ceil(min(p0, p1)), math.floor(max(p0, p1)) + 1)
                ts.append((lines - p0) / (p1 - p0))
        t = np.unique(np.clip(np.concatenate(ts), 0.0, 1.0))
        mid = (t[:-1] + t[1:]) / 2.0 if t.size > 1 else t
        cols = np.floor(u0 + (u1 - u0) * mid).astype(np.intp)
        rows = np.floor(v0 + (v1 - v0) * mid).astype(np.intp)
        height, width = mask.shape
        if cols.min() < 0 or rows.min() < 0 or cols.max() >= width or rows.max() >= height:
            return False
        return not mask[rows, cols].any()
