"""The simulated ``bt_navigator``: ``navigate_to_pose`` and ``navigate_through_poses``.

Nav2's observable behaviour (Jazzy): goals are refused unless the node is ACTIVE, and goals
in a frame other than the global frame are rejected; an accepted goal is planned and driven
by the :class:`~sar_framework.sim.navigation.Navigator`; feedback carries ``current_pose``,
``distance_remaining``, ``navigation_time``, ``estimated_time_remaining``,
``number_of_recoveries`` (always 0) and, through poses, ``number_of_poses_remaining``. Without
a robot pose (AMCL not seeded) a goal ends ABORTED with ``NONE`` and bt_navigator's "Initial
robot pose is not available"; a failed plan ends ABORTED with the planner's code, as Jazzy's
``error_code_names`` report it. ``navigate_through_poses`` needs the full ``nav2_msgs``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from nav2_msgs.action import NavigateToPose
from rclpy.action import GoalResponse

from sar_framework.sim.faults import Faults
from sar_framework.sim.goal_actions import Failure, GoalAction, GoalGate, serve_goal_action
from sar_framework.sim.goals import ERROR_NONE, Goal, Progress
from sar_framework.sim.lifecycle import Nav2LifecycleNode, optional_type
from sar_framework.sim.messages import duration_msg, pose_stamped, pose_to_2d

EventSink = Callable[..., None]
"""Called as ``sink(event, **fields)`` for goal requests the navigator never sees."""

NO_ROBOT_POSE = ("Initial robot pose is not available: AMCL has no initial pose "
                 "(publish /initialpose)")


class BtNavigator:
    """The simulator's ``bt_navigator`` lifecycle node.

    Args:
        gate: Shared goal gate (navigator, clock, shutdown).
        localized: Returns whether the robot's map pose is known (AMCL seeded).
        faults: Injected faults (``reject_goals``, ``accept_delay_wall_s``).
        global_frame: Goals must be in this frame.
        event_sink: Told about rejected goal requests (for the trace).
    """

    def __init__(self, gate: GoalGate, localized: Callable[[], bool], *,
                 faults: Faults | None = None, global_frame: str = "map",
                 event_sink: EventSink | None = None) -> None:
        self.node = Nav2LifecycleNode("bt_navigator")
        self._gate = gate
        self._localized = localized
        self._faults = faults or Faults()
        self._global_frame = global_frame
        self._event_sink = event_sink
        self.servers = [serve_goal_action(
            self.node, "navigate_to_pose", gate,
            GoalAction(NavigateToPose, self._start_to_pose, self._fill_feedback),
            lambda request: self._check(request, [request.pose]),
        )]
        through = optional_type("nav2_msgs.action", "NavigateThroughPoses",
                                needed_by="navigate_through_poses")
        if through is not None:
            self.servers.append(serve_goal_action(
                self.node, "navigate_through_poses", gate,
                GoalAction(through, self._start_through_poses, self._fill_feedback),
                lambda request: self._check(request, list(request.poses)),
            ))

    # ------------------------------------------------------------------ goal requests

    def _reject(self, reason: str, poses: list[Any]) -> GoalResponse:
        self.node.get_logger().warning(f"Rejecting goal: {reason}")
        if self._event_sink is not None:
            target = pose_to_2d(poses[-1].pose) if poses else None
            self._event_sink(
                "rejected", x=target.x if target else None, y=target.y if target else None,
                yaw=target.yaw if target else None,
                frame=poses[-1].header.frame_id if poses else "", reason=reason,
            )
        return GoalResponse.REJECT

    def _check(self, _request: Any, poses: list[Any]) -> GoalResponse:
        """Accept or reject a goal request (runs in an executor thread)."""
        if self._faults.accept_delay_wall_s > 0.0:
            self._gate.closing.wait(self._faults.accept_delay_wall_s)  # wall seconds, by design
        if self._gate.closing.is_set():
            return self._reject("the simulator is shutting down", poses)
        if self._faults.reject_goals:
            return self._reject("injected fault (reject_goals)", poses)
        if not poses:
            return self._reject("no poses to navigate through", poses)
        for pose in poses:
            frame = pose.header.frame_id
            if frame.lstrip("/") != self._global_frame:
                return self._reject(
                    f"goal frame {frame!r} is not the global frame {self._global_frame!r}", poses
                )
            p, q = pose.pose.position, pose.pose.orientation
            if not all(math.isfinite(v) for v in (p.x, p.y, p.z, q.x, q.y, q.z, q.w)):
                return self._reject("the goal pose holds a non-finite value", poses)
        return GoalResponse.ACCEPT

    # ------------------------------------------------------------------ execution

    def _start_to_pose(self, request: Any) -> Goal | Failure:
        if not self._localized():
            return ERROR_NONE, NO_ROBOT_POSE
        goal = self._gate.navigator.start(pose_to_2d(request.pose.pose))
        self._log_start(goal)
        return goal

    def _start_through_poses(self, request: Any) -> Goal | Failure:
        if not self._localized():
            return ERROR_NONE, NO_ROBOT_POSE
        poses = [pose_to_2d(p.pose) for p in request.poses]
        goal = self._gate.navigator.start(poses[-1], via=poses[:-1])
        self._log_start(goal)
        return goal

    def _log_start(self, goal: Goal) -> None:
        t = goal.target
        self.node.get_logger().info(
            f"Goal {goal.number}: navigating to ({t.x:.2f}, {t.y:.2f}, yaw {t.yaw:.2f})")

    def _fill_feedback(self, feedback: Any, _goal: Goal, progress: Progress) -> None:
        feedback.current_pose = pose_stamped(progress.pose, self._global_frame,
                                             self._gate.now_ns())
        feedback.distance_remaining = float(progress.distance_remaining)
        feedback.navigation_time = duration_msg(progress.navigation_time)
        feedback.estimated_time_remaining = duration_msg(progress.estimated_time_remaining)
        feedback.number_of_recoveries = 0
        if hasattr(feedback, "number_of_poses_remaining"):
            feedback.number_of_poses_remaining = progress.poses_remaining

    def destroy(self) -> None:
        """Destroy the action servers and the node."""
        for server in self.servers:
            server.destroy()
        self.node.destroy_node()
