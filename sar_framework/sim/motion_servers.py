"""The simulated ``controller_server``, ``behavior_server`` and ``waypoint_follower``.

- ``controller_server``: ``follow_path`` drives the given path (no planning) from the
  path pose nearest the robot, feedback ``distance_to_goal`` / ``speed``; ids are checked
  (:mod:`.plugin_ids`); it owns ``/local_costmap/local_costmap``.
- ``behavior_server``: ``spin`` (turn by ``target_yaw``), ``backup`` (drive back
  ``|target.x|`` at ``|speed|``), ``drive_on_heading`` (drive ``target.x``, its sign the
  speed's; INVALID_INPUT when they differ) and ``wait``, each with Nav2's ``time_allowance``
  timeout; a straight motion fails with COLLISION_AHEAD when its way is blocked (a wall, a
  blocked area, a phantom of either costmap) and with INVALID_INPUT for a sideways target.
  A completed spin, backup or drive_on_heading counts a stuck controller down.
- ``waypoint_follower``: ``follow_waypoints`` navigates to each pose in turn (from
  ``goal_index``), feedback ``current_waypoint``; a failed waypoint is reported in
  ``missed_waypoints`` and the rest are still visited (``stop_on_failure: false``).

Every action needs the full ``nav2_msgs``; without it (fallback tier) the nodes exist but
offer no action.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from rclpy.action.server import ServerGoalHandle

from sar_framework.sim.costmap_servers import costmap_node
from sar_framework.sim.costmaps import Layer
from sar_framework.sim.goal_actions import (
    Failure,
    GoalAction,
    GoalGate,
    elapsed_msg,
    follow_goal,
    serve_goal_action,
)
from sar_framework.sim.goals import Goal, Outcome, Progress
from sar_framework.sim.lifecycle import Nav2LifecycleNode, optional_type
from sar_framework.sim.messages import duration_msg, pose_to_2d
from sar_framework.sim.plugin_ids import CONTROLLERS, GOAL_CHECKERS, PROGRESS_CHECKERS, unknown_id
from sar_framework.sim.world import Pose2D


def _seconds(duration: Any) -> float:
    return duration.sec + duration.nanosec * 1e-9


def _elapsed_result(result: Any, goal: Goal) -> None:
    result.total_elapsed_time = elapsed_msg(goal)


class ControllerServer:
    """``controller_server`` (+ the local costmap): ``follow_path``.

    Args:
        gate: Shared goal gate.
    """

    def __init__(self, gate: GoalGate) -> None:
        self.node = Nav2LifecycleNode("controller_server")
        self.costmap = costmap_node(Layer.LOCAL, self.node, gate.navigator)
        self._gate = gate
        self._kind = optional_type("nav2_msgs.action", "FollowPath", needed_by="follow_path")
        if self._kind is not None:
            serve_goal_action(self.node, "follow_path", gate,
                              GoalAction(self._kind, self._start, self._feedback))

    def _start(self, request: Any) -> Goal | Failure:
        codes = self._kind.Result
        for given, known, what, code in (
                (request.controller_id, CONTROLLERS, "controller", codes.INVALID_CONTROLLER),
                (request.goal_checker_id, GOAL_CHECKERS, "goal checker", codes.UNKNOWN),
                (request.progress_checker_id, PROGRESS_CHECKERS, "progress checker",
                 codes.UNKNOWN)):
            bad_id = unknown_id(given, known, what)
            if bad_id is not None:
                return code, bad_id
        poses = list(request.path.poses)
        if not poses:
            return self._kind.Result.INVALID_PATH, "Path is empty."
        points = [(p.pose.position.x, p.pose.position.y) for p in poses]
        return self._gate.navigator.start_path(points, pose_to_2d(poses[-1].pose))

    def _feedback(self, feedback: Any, _goal: Goal, progress: Progress) -> None:
        feedback.distance_to_goal = float(progress.distance_remaining)
        feedback.speed = float(progress.linear)


class BehaviorServer:
    """``behavior_server``: ``spin``, ``backup`` and ``wait``.

    Args:
        gate: Shared goal gate.
    """

    def __init__(self, gate: GoalGate) -> None:
        self.node = Nav2LifecycleNode("behavior_server")
        self._gate = gate
        behaviours: dict[str, tuple[str, Callable[[Any, Any], Goal | Failure],
                                    Callable[[Any, Goal, Progress], None]]] = {
            "spin": ("Spin", self._start_spin, self._spin_feedback),
            "backup": ("BackUp", self._start_backup, self._backup_feedback),
            "drive_on_heading": ("DriveOnHeading", self._start_drive_on_heading,
                                 self._backup_feedback),
            "wait": ("Wait", self._start_wait, self._wait_feedback),
        }
        for name, (type_name, start, feedback) in behaviours.items():
            kind = optional_type("nav2_msgs.action", type_name, needed_by=name)
            if kind is not None:
                serve_goal_action(self.node, name, gate, GoalAction(
                    kind, lambda request, k=kind, s=start: s(k, request), feedback,
                    _elapsed_result))

    def _start_spin(self, kind: Any, request: Any) -> Goal | Failure:
        return self._gate.navigator.start_spin(
            request.target_yaw, _seconds(request.time_allowance), kind.Result.TIMEOUT)

    def _start_backup(self, kind: Any, request: Any) -> Goal | Failure:
        return self._start_straight(kind, request, -abs(request.target.x))

    def _start_drive_on_heading(self, kind: Any, request: Any) -> Goal | Failure:
        if (request.target.x > 0.0) != (request.speed > 0.0):
            return kind.Result.INVALID_INPUT, "Speed and command sign did not match"
        return self._start_straight(kind, request, request.target.x)

    def _start_straight(self, kind: Any, request: Any, distance: float) -> Goal | Failure:
        """BackUp and DriveOnHeading (Nav2's BackUp is a DriveOnHeading backwards)."""
        if request.target.y != 0.0 or request.target.z != 0.0:
            return kind.Result.INVALID_INPUT, "DrivingOnHeading in Y and Z not supported"
        if request.speed == 0.0:
            return kind.Result.INVALID_INPUT, "Speed must not be zero"
        navigator = self._gate.navigator
        here = navigator.state().pose
        end = Pose2D(here.x + distance * math.cos(here.yaw), here.y + distance * math.sin(here.yaw),
                     here.yaw)
        if not navigator.path_is_clear(here, end):
            return kind.Result.COLLISION_AHEAD, "Collision Ahead - Exiting DriveOnHeading"
        return navigator.start_straight(distance, abs(request.speed),
                                        _seconds(request.time_allowance), kind.Result.TIMEOUT)

    def _start_wait(self, _kind: Any, request: Any) -> Goal | Failure:
        return self._gate.navigator.start_wait(_seconds(request.time))

    @staticmethod
    def _spin_feedback(feedback: Any, _goal: Goal, progress: Progress) -> None:
        feedback.angular_distance_traveled = float(progress.motion_done)

    @staticmethod
    def _backup_feedback(feedback: Any, _goal: Goal, progress: Progress) -> None:
        feedback.distance_traveled = float(progress.motion_done)

    @staticmethod
    def _wait_feedback(feedback: Any, _goal: Goal, progress: Progress) -> None:
        feedback.time_left = duration_msg(progress.time_left)


class WaypointFollower:
    """``waypoint_follower``: ``follow_waypoints``.

    Args:
        gate: Shared goal gate.
        localized: Whether the robot's map pose is known.
    """

    def __init__(self, gate: GoalGate, localized: Callable[[], bool]) -> None:
        self.node = Nav2LifecycleNode("waypoint_follower")
        self._gate = gate
        self._localized = localized
        self._kind = optional_type("nav2_msgs.action", "FollowWaypoints",
                                   needed_by="follow_waypoints")
        self._missed = optional_type("nav2_msgs.msg", "MissedWaypoint",
                                     needed_by="follow_waypoints")
        if self._kind is not None and self._missed is not None:
            self.node.action_server(self._kind, "follow_waypoints", self._execute)

    def _execute(self, handle: ServerGoalHandle) -> Any:
        self._gate.enter()
        try:
            return self._run(handle)
        finally:
            self._gate.leave()

    def _run(self, handle: ServerGoalHandle) -> Any:
        kind, request = self._kind, handle.request
        result, feedback = kind.Result(), kind.Feedback()
        log = self.node.get_logger()
        poses = list(request.poses)
        log.info(f"Received follow waypoint request with {len(poses)} waypoints.")
        generation = self._gate.navigator.generation
        for index in range(request.goal_index, len(poses)):
            feedback.current_waypoint = index
            handle.publish_feedback(feedback)
            if not self._localized():
                goal = None
                code = 0
            else:
                goal = self._gate.navigator.start(pose_to_2d(poses[index].pose))
                follow_goal(self._gate, handle, goal, feedback, lambda _msg: None)
                code = goal.error_code
            if goal is not None and goal.outcome is Outcome.CANCELED:
                handle.canceled()
                return result
            if self._gate.closing.is_set() or self._gate.navigator.generation != generation \
                    or (goal is not None and goal.outcome
                                               is Outcome.ABORTED and not goal.error_msg):
                handle.abort()  # shut down, or preempted by another goal
                return result
            if goal is None or goal.outcome is not Outcome.SUCCEEDED:
                log.warning(f"Failed to process waypoint {index} in waypoint list.")
                result.missed_waypoints.append(self._missed(
                    index=index, goal=poses[index], error_code=code))
            else:
                log.info(f"Succeeded processing waypoint {index}, moving to next.")
        log.info(f"Completed all {len(poses)} waypoints requested.")
        handle.succeed()
        return result
