"""The simulated ``planner_server`` and ``smoother_server``, and the two costmap nodes.

- ``planner_server``: ``compute_path_to_pose`` and ``compute_path_through_poses`` with the
  simulator's A* planner (the one ``navigate_to_pose`` drives), as a dense ``nav_msgs/Path``
  (one pose per map cell, headings along the path, the goal's orientation last), with
  Jazzy's ComputePathToPose error codes; it owns ``/global_costmap/global_costmap``.
- ``smoother_server``: ``smooth_path``, Nav2's simple smoother (gradient steps pulling each
  inner point towards its neighbours, ends fixed), SMOOTHED_PATH_IN_COLLISION on request.
- ``controller_server`` owns ``/local_costmap/local_costmap`` (see motion_servers).

The costmap nodes and ``is_path_valid`` are in :mod:`~sar_framework.sim.costmap_servers`.
Every action here needs the full ``nav2_msgs``; without it (fallback tier) the server node
exists but offers no action.
"""

from __future__ import annotations

import itertools
import math
import time
from collections.abc import Callable
from typing import Any

import numpy as np
from nav_msgs.msg import Path

from sar_framework.sim.costmap_servers import costmap_node, serve_is_path_valid
from sar_framework.sim.costmaps import Layer
from sar_framework.sim.lifecycle import Nav2LifecycleNode, optional_type
from sar_framework.sim.messages import duration_msg, pose_stamped, pose_to_2d, time_msg
from sar_framework.sim.navigation import Navigator
from sar_framework.sim.planner import PlanningError
from sar_framework.sim.plugin_ids import PLANNERS, SMOOTHERS, unknown_id
from sar_framework.sim.world import Pose2D

SMOOTH_W_DATA = 0.2
"""Nav2 SimpleSmoother's ``w_data`` (pull towards the original point)."""
SMOOTH_W_SMOOTH = 0.3
"""Nav2 SimpleSmoother's ``w_smooth`` (pull towards the neighbours)."""
SMOOTH_MAX_ITS = 1000
SMOOTH_TOLERANCE = 1e-10


def dense_path(points: list[tuple[float, float]], goal_yaw: float, frame: str, stamp_ns: int,
               spacing: float) -> Path:
    """Return a ``nav_msgs/Path`` through ``points`` with a pose every ``spacing`` metres."""
    msg = Path()
    msg.header.frame_id = frame
    msg.header.stamp = time_msg(stamp_ns)
    for (ax, ay), (bx, by) in itertools.pairwise(points):
        length = math.hypot(bx - ax, by - ay)
        heading = math.atan2(by - ay, bx - ax)
        for i in range(max(1, math.ceil(length / spacing))):
            f = i * spacing / length if length > 0 else 0.0
            msg.poses.append(pose_stamped(Pose2D(ax + f * (bx - ax), ay + f * (by - ay),
                                                 heading), frame, stamp_ns))
    last = points[-1]
    msg.poses.append(pose_stamped(Pose2D(last[0], last[1], goal_yaw), frame, stamp_ns))
    return msg


def smooth(points: np.ndarray) -> np.ndarray:
    """Nav2's simple smoother on an ``(n, 2)`` array of points (ends stay fixed)."""
    new = points.copy()
    for _ in range(SMOOTH_MAX_ITS):
        before = new.copy()
        inner = slice(1, len(new) - 1)
        new[inner] += SMOOTH_W_DATA * (points[inner] - new[inner]) + SMOOTH_W_SMOOTH * (
            new[2:] + new[:-2] - 2.0 * new[inner])
        if float(np.abs(new - before).sum()) < SMOOTH_TOLERANCE:
            break
    return new


class PlannerServer:
    """``planner_server`` (+ the global costmap).

    Args:
        navigator: Plans (``plan_through``) and knows the robot's pose.
        now_ns: Simulated time.
        localized: Whether the robot's map pose is known.
        global_frame: The map frame.
        resolution: Map resolution (path spacing), metres.
    """

    def __init__(self, navigator: Navigator, now_ns: Callable[[], int],
                 localized: Callable[[], bool], *, global_frame: str = "map",
                 resolution: float = 0.05) -> None:
        self.node = Nav2LifecycleNode("planner_server")
        self.costmap = costmap_node(Layer.GLOBAL, self.node, navigator)
        serve_is_path_valid(self.node, navigator)
        self._navigator = navigator
        self._now_ns = now_ns
        self._localized = localized
        self._frame = global_frame
        self._spacing = resolution
        for action, name, poses in (
            ("ComputePathToPose", "compute_path_to_pose", lambda r: [r.goal]),
            ("ComputePathThroughPoses", "compute_path_through_poses", lambda r: list(r.goals)),
        ):
            kind = optional_type("nav2_msgs.action", action, needed_by=name)
            if kind is not None:
                self.node.action_server(kind, name, self._executor(kind, poses))

    def _executor(self, kind: Any, goals_of: Callable[[Any], list[Any]]
                  ) -> Callable[[Any], Any]:
        def execute(handle: Any) -> Any:
            result = kind.Result()
            started = time.monotonic()
            request = handle.request
            goals = goals_of(request)
            bad_id = unknown_id(request.planner_id, PLANNERS, "planner")
            if bad_id is not None:
                result.error_code, result.error_msg = kind.Result.INVALID_PLANNER, bad_id
            elif not request.use_start and not self._localized():
                result.error_code = kind.Result.TF_ERROR
                result.error_msg = "Could not get the robot pose: AMCL has no initial pose"
            elif not goals:
                result.error_code = kind.Result.NO_VIAPOINTS_GIVEN \
                    if hasattr(kind.Result, "NO_VIAPOINTS_GIVEN") else kind.Result.UNKNOWN
                result.error_msg = "no goal poses given"
            else:
                start = pose_to_2d(request.start.pose) if request.use_start \
                    else self._navigator.state().pose
                targets = [pose_to_2d(g.pose) for g in goals]
                try:
                    legs = self._navigator.plan_through(start, targets)
                    points = [p for i, leg in enumerate(legs) for p in (leg if i == 0
                                                                         else leg[1:])]
                    result.path = dense_path(points, targets[-1].yaw, self._frame,
                                             self._now_ns(), self._spacing)
                except PlanningError as exc:
                    result.error_code, result.error_msg = exc.error_code, str(exc)
            result.planning_time = duration_msg(time.monotonic() - started)
            if result.error_code:
                self.node.get_logger().warning(f"Planning failed: {result.error_msg}")
                handle.abort()
            else:
                handle.succeed()
            return result

        return execute


class SmootherServer:
    """``smoother_server``: ``smooth_path``.

    Args:
        is_free: Whether a map point is free (for ``check_for_collisions``).
    """

    def __init__(self, is_free: Callable[[float, float], bool]) -> None:
        self.node = Nav2LifecycleNode("smoother_server")
        self._is_free = is_free
        self._kind = optional_type("nav2_msgs.action", "SmoothPath", needed_by="smooth_path")
        if self._kind is not None:
            self.node.action_server(self._kind, "smooth_path", self._execute)

    def _execute(self, handle: Any) -> Any:
        kind, request = self._kind, handle.request
        result = kind.Result()
        started = time.monotonic()
        poses = list(request.path.poses)
        result.path = request.path
        bad_id = unknown_id(request.smoother_id, SMOOTHERS, "smoother")
        if bad_id is not None:
            result.error_code, result.error_msg = kind.Result.INVALID_SMOOTHER, bad_id
        elif len(poses) < 2:
            result.error_code, result.error_msg = kind.Result.INVALID_PATH, "path too short"
        else:
            points = np.array([(p.pose.position.x, p.pose.position.y) for p in poses])
            smoothed = smooth(points)
            for pose, (x, y) in zip(result.path.poses, smoothed, strict=True):
                pose.pose.position.x, pose.pose.position.y = float(x), float(y)
            if request.check_for_collisions and not all(self._is_free(x, y)
                                                        for x, y in smoothed):
                result.error_code = kind.Result.SMOOTHED_PATH_IN_COLLISION
                result.error_msg = "the smoothed path is in collision"
        result.smoothing_duration = duration_msg(time.monotonic() - started)
        result.was_completed = result.error_code == 0
        if result.error_code:
            handle.abort()
        else:
            handle.succeed()
        return result
