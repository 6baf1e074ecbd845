"""PathCosts: one auction round's bids, from the robot's own Nav2 planner.

For each announced zone a ``ComputePathToPose`` goal (from the robot's pose, ``use_start``
false) is sent at once to the relative ``compute_path_to_pose`` action; the cost of a zone
is the length of its path in metres, ``inf`` when the planner answers that it failed or
gives an empty path. A zone the planner did not answer for (no server, a goal not
accepted, no answer within the bound: a busy or starting robot) gets no cost at all: not
knowing is not "cannot reach", and the coordinator abandons zones on "cannot reach".
Polled by tick, never blocking. Imports ROS lazily.
"""

from __future__ import annotations

import itertools
import math
import time
from collections.abc import Mapping
from typing import Any

from sar_framework.leaves import STATUS_SUCCEEDED, GoalBatch

from ._pose_target import yaw_to_quaternion


def path_length(poses: Any) -> float:
    """The length in metres of a ``nav_msgs/Path``'s poses (``inf`` for an empty path)."""
    if not poses:
        return math.inf
    points = [(p.pose.position.x, p.pose.position.y) for p in poses]
    return sum(math.dist(a, b) for a, b in itertools.pairwise(points))


class PathCosts:
    """The planner costs of one round's zones.

    Args:
        planner: The robot's ``ComputePathToPose`` goals
            (:class:`~sar_framework.leaves.GoalBatch`).
        frame_id: The goals' frame.
        zones: Zone id -> ``{"x", "y", "yaw"}``.
        bound_wall_s: Zones without an answer after this many wall seconds get no cost.
        stamp: The goals' header stamp (``builtin_interfaces/Time``).
    """

    def __init__(self, planner: GoalBatch, frame_id: str, *,
                 zones: Mapping[str, Mapping[str, float]], bound_wall_s: float,
                 stamp: Any) -> None:
        self._planner = planner
        self._started = time.monotonic()
        self._bound = bound_wall_s
        self.costs: dict[str, float] = {}
        planner.drop()  # a previous round's unanswered goals count no more
        if not planner.server_is_ready():
            return  # nothing known: no costs
        for zone_id, pose in zones.items():
            goal = planner.action_type.Goal()
            goal.goal.header.frame_id = frame_id
            goal.goal.header.stamp = stamp
            goal.goal.pose.position.x = float(pose["x"])
            goal.goal.pose.position.y = float(pose["y"])
            q = goal.goal.pose.orientation
            q.x, q.y, q.z, q.w = yaw_to_quaternion(float(pose["yaw"]))
            goal.use_start = False
            planner.send(zone_id, goal)

    def poll(self) -> dict[str, float] | None:
        """Return the zones' costs once every answer came (or the bound passed), else None.

        Zones without an answer (or whose goal was not accepted) are left out of the result.
        """
        for zone_id, end in self._planner.poll().items():
            if end.failure is not None:
                continue  # not accepted: not knowing is not "cannot reach"
            ok = end.status == STATUS_SUCCEEDED and end.result is not None
            self.costs[zone_id] = path_length(end.result.path.poses) if ok else math.inf
        if self._planner.pending:
            if time.monotonic() - self._started < self._bound:
                return None
            self._planner.drop()  # unanswered: no cost
        return dict(self.costs)
