"""Plane geometry of paths (plain Python): nearest points on segments, pruning a path."""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence

Point = tuple[float, float]


def closest_on_segment(p: Point, a: Point, b: Point) -> Point:
    """The point of segment ``a``-``b`` nearest ``p``."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    length_sq = dx * dx + dy * dy
    t = 0.0 if length_sq == 0.0 else ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / length_sq
    t = min(max(t, 0.0), 1.0)
    return a[0] + t * dx, a[1] + t * dy


def segment_distance(p: Point, a: Point, b: Point) -> float:
    """Distance from ``p`` to segment ``a``-``b``."""
    return math.dist(p, closest_on_segment(p, a, b))


def prune_to_nearest(points: Sequence[Point], here: Point, search_m: float) -> list[Point]:
    """Drop the part of a path before its point nearest ``here``, as Nav2's controllers do.

    Args:
        points: The path (at least one point).
        here: The robot's position.
        search_m: Only segments starting within this arc length of the path's start are
            searched (a path that passes the robot again later is not cut short).

    Returns:
        The path from the nearest point on (``points`` itself when that is its start).
    """
    best = (math.dist(points[0], here), 0, points[0])
    arc = 0.0
    for i, (a, b) in enumerate(itertools.pairwise(points)):
        if arc > search_m:
            break
        nearest = closest_on_segment(here, a, b)
        distance = math.dist(nearest, here)
        if distance < best[0] - 1e-9:
            best = (distance, i, nearest)
        arc += math.dist(a, b)
    _, index, nearest = best
    if index == 0 and nearest == points[0]:
        return list(points)
    rest = list(points[index + 1:])
    return rest if rest and rest[0] == nearest else [nearest, *rest]
