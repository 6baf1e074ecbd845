"""The ``navigate_to_pose`` action server of the simulated ``bt_navigator`` node.

Serves ``nav2_msgs/action/NavigateToPose`` with Nav2's observable behaviour (Jazzy):
goals in a frame other than the global frame are rejected; an accepted goal is planned
and driven by the :class:`~sar_framework.sim.navigation.Navigator`; feedback carries
``current_pose``, ``distance_remaining``, ``navigation_time``,
``estimated_time_remaining`` and ``number_of_recoveries`` (always 0); the goal ends
SUCCEEDED, ABORTED (``error_code``/``error_msg`` set, or an empty result when preempted by
a newer goal) or CANCELED. All times are simulated time.

Each goal's execute callback waits in an executor thread (the node must be spun by a
``MultiThreadedExecutor``); the physics loop runs elsewhere and is never blocked by it.
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable
from typing import Any

from nav2_msgs.action import NavigateToPose
from rclpy.action import ActionServer, CancelResponse, GoalResponse
from rclpy.action.server import ServerGoalHandle
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.node import Node

from sar_framework.sim.faults import Faults
from sar_framework.sim.lifecycle import serve_active_state
from sar_framework.sim.messages import duration_msg, pose_stamped, pose_to_2d
from sar_framework.sim.navigation import Goal, Navigator, Outcome

POLL_PERIOD_S = 0.01
"""Wall seconds between two checks of a running goal (cancel requests, feedback)."""
MAX_FEEDBACK_WALL_HZ = 50.0
"""Feedback is never published faster than this many times per wall second."""

EventSink = Callable[..., None]
"""Called as ``sink(event, **fields)`` for goal requests the navigator never sees."""


class NavigateToPoseServer:
    """The simulator's ``bt_navigator`` node: ``navigate_to_pose`` and ``get_state``.

    Args:
        navigator: Runs the goals.
        now_ns: Returns the simulated time, nanoseconds.
        localized: Returns whether the robot's map pose is known (AMCL seeded).
        faults: Injected faults (``reject_goals``, ``accept_delay_s``).
        global_frame: Goals must be in this frame.
        feedback_period_s: Simulated seconds between feedback messages.
        action_name: The action's name.
        event_sink: Told about rejected goal requests (for the trace).
    """

    def __init__(
        self,
        navigator: Navigator,
        now_ns: Callable[[], int],
        localized: Callable[[], bool],
        *,
        faults: Faults | None = None,
        global_frame: str = "map",
        feedback_period_s: float = 0.1,
        action_name: str = "navigate_to_pose",
        event_sink: EventSink | None = None,
    ) -> None:
        self.node = Node("bt_navigator")
        self._navigator = navigator
        self._now_ns = now_ns
        self._localized = localized
        self._faults = faults or Faults()
        self._global_frame = global_frame
        self._feedback_period_s = feedback_period_s
        self._event_sink = event_sink
        self._closing = threading.Event()
        self._idle = threading.Condition()
        self._executing = 0
        group = ReentrantCallbackGroup()
        serve_active_state(self.node, group)
        self._server = ActionServer(
            self.node,
            NavigateToPose,
            action_name,
            execute_callback=self._execute,
            goal_callback=self._on_goal,
            cancel_callback=self._on_cancel,
            callback_group=group,
        )

    # ------------------------------------------------------------------ goal requests

    def _reject(self, reason: str, request: NavigateToPose.Goal) -> GoalResponse:
        self.node.get_logger().warning(f"Rejecting goal: {reason}")
        if self._event_sink is not None:
            target = pose_to_2d(request.pose.pose)
            self._event_sink(
                "rejected", x=target.x, y=target.y, yaw=target.yaw,
                frame=request.pose.header.frame_id, reason=reason,
            )
        return GoalResponse.REJECT

    def _on_goal(self, request: NavigateToPose.Goal) -> GoalResponse:
        """Accept or reject a goal request (runs in an executor thread)."""
        if self._faults.accept_delay_s > 0.0:
            self._closing.wait(self._faults.accept_delay_s)  # wall seconds, by design
        if self._closing.is_set():
            return self._reject("the simulator is shutting down", request)
        if self._faults.reject_goals:
            return self._reject("injected fault (reject_goals)", request)
        frame = request.pose.header.frame_id
        if frame.lstrip("/") != self._global_frame:
            return self._reject(
                f"goal frame {frame!r} is not the global frame {self._global_frame!r}", request
            )
        position = request.pose.pose.position
        orientation = request.pose.pose.orientation
        values = (position.x, position.y, position.z, orientation.x, orientation.y,
                  orientation.z, orientation.w)
        if not all(math.isfinite(v) for v in values):
            return self._reject("the goal pose holds a non-finite value", request)
        return GoalResponse.ACCEPT

    def _on_cancel(self, _goal_handle: ServerGoalHandle) -> CancelResponse:
        """Accept every cancel request; the goal's execute callback carries it out."""
        return CancelResponse.ACCEPT

    # ------------------------------------------------------------------ execution

    def _execute(self, goal_handle: ServerGoalHandle) -> NavigateToPose.Result:
        """Run one goal to its end (blocks an executor thread, polling every 10 ms)."""
        with self._idle:
            self._executing += 1
        try:
            return self._run(goal_handle)
        finally:
            with self._idle:
                self._executing -= 1
                self._idle.notify_all()

    def _run(self, goal_handle: ServerGoalHandle) -> NavigateToPose.Result:
        log = self.node.get_logger()
        result = NavigateToPose.Result()
        target = pose_to_2d(goal_handle.request.pose.pose)
        if not self._localized():
            result.error_code = NavigateToPose.Result.TF_ERROR
            result.error_msg = (
                "robot pose is not available: AMCL has no initial pose (publish /initialpose)"
            )
            log.error(f"Goal aborted: {result.error_msg}")
            goal_handle.abort()
            return result
        goal = self._navigator.start(target)
        log.info(
            f"Goal {goal.number}: navigating to ({target.x:.2f}, {target.y:.2f}, "
            f"yaw {target.yaw:.2f})"
        )
        self._follow(goal_handle, goal)
        result.error_code = goal.error_code
        result.error_msg = goal.error_msg
        elapsed = (goal.finished_s or goal.started_s) - goal.started_s
        if goal.outcome is Outcome.SUCCEEDED:
            log.info(f"Goal {goal.number} succeeded in {elapsed:.1f} s (sim).")
            goal_handle.succeed()
        elif goal.outcome is Outcome.CANCELED:
            log.info(f"Goal {goal.number} canceled after {elapsed:.1f} s (sim).")
            goal_handle.canceled()
        else:
            reason = goal.error_msg or "preempted by a newer goal"
            log.warning(f"Goal {goal.number} aborted after {elapsed:.1f} s (sim): {reason}")
            goal_handle.abort()
        return result

    def _follow(self, goal_handle: ServerGoalHandle, goal: Goal) -> None:
        """Wait for ``goal`` to end, forwarding cancel requests and publishing feedback."""
        feedback = NavigateToPose.Feedback()
        next_feedback_ns = 0
        next_feedback_wall = 0.0
        while not goal.done.wait(POLL_PERIOD_S):
            if goal_handle.is_cancel_requested:
                self._navigator.cancel(goal)
                goal.done.wait()  # set by cancel(), or by a concurrent end
                return
            now_ns, wall = self._now_ns(), time.monotonic()
            if now_ns >= next_feedback_ns and wall >= next_feedback_wall:
                self._fill_feedback(feedback, goal, now_ns)
                goal_handle.publish_feedback(feedback)
                next_feedback_ns = now_ns + round(self._feedback_period_s * 1e9)
                next_feedback_wall = wall + 1.0 / MAX_FEEDBACK_WALL_HZ

    def _fill_feedback(self, feedback: Any, goal: Goal, now_ns: int) -> None:
        progress = self._navigator.progress(goal)
        feedback.current_pose = pose_stamped(progress.pose, self._global_frame, now_ns)
        feedback.distance_remaining = float(progress.distance_remaining)
        feedback.navigation_time = duration_msg(progress.navigation_time)
        feedback.estimated_time_remaining = duration_msg(progress.estimated_time_remaining)
        feedback.number_of_recoveries = 0

    # ------------------------------------------------------------------ shutdown

    def close(self, reason: str, timeout_s: float = 0.5) -> Goal | None:
        """Stop taking goals, abort the running one and wait for its execute callback.

        The executor must keep spinning a little longer afterwards: rclpy sends the
        result to a waiting client from a follow-up executor task.

        Args:
            reason: ``error_msg`` of the aborted goal.
            timeout_s: Wall seconds to wait for execute callbacks to return.

        Returns:
            The aborted goal, or None if no goal was running.
        """
        self._closing.set()
        goal = self._navigator.abort_active(reason)
        if goal is not None:
            self.node.get_logger().warning(f"Goal {goal.number} aborted: {reason}")
        with self._idle:
            self._idle.wait_for(lambda: self._executing == 0, timeout=timeout_s)
        return goal

    def destroy(self) -> None:
        """Destroy the action server and the node."""
        self._server.destroy()
        self.node.destroy_node()
