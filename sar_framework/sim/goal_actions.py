"""Serve a navigator goal as a ROS action: start, feedback, cancel, result, shutdown.

Every motion action of the simulated Nav2 (``navigate_to_pose``, ``follow_path``, ``spin``,
...) runs the same way: the goal is started on the shared
:class:`~sar_framework.sim.navigation.Navigator` (a newer goal of any action preempts it,
ending it ABORTED with an empty result, as Nav2's servers do), its execute callback waits in
an executor thread (spin the nodes with a ``MultiThreadedExecutor``), forwards a cancel
request, publishes feedback at a simulated rate, and ends SUCCEEDED, CANCELED or ABORTED with
the goal's ``error_code`` / ``error_msg``. All times are simulated time.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from rclpy.action.server import ServerGoalHandle

from sar_framework.sim.goals import Goal, Outcome, Progress
from sar_framework.sim.lifecycle import Nav2LifecycleNode
from sar_framework.sim.messages import duration_msg
from sar_framework.sim.navigation import Navigator

POLL_PERIOD_S = 0.01
"""Wall seconds between two checks of a running goal (cancel requests, feedback)."""
MAX_FEEDBACK_WALL_HZ = 50.0
"""Feedback is never published faster than this many times per wall second."""

Failure = tuple[int, str]
"""``(error_code, error_msg)`` of a goal that ends before it starts."""


class GoalGate:
    """Shared by every goal action: counts running execute callbacks, closes at shutdown.

    Args:
        navigator: The navigator the goals run on.
        now_ns: Returns the simulated time, nanoseconds.
        feedback_period_s: Simulated seconds between feedback messages.
    """

    def __init__(self, navigator: Navigator, now_ns: Callable[[], int],
                 feedback_period_s: float = 0.1) -> None:
        self.navigator = navigator
        self.now_ns = now_ns
        self.feedback_period_s = feedback_period_s
        self.closing = threading.Event()
        self._idle = threading.Condition()
        self._executing = 0
        self._published = threading.Condition()
        self._published_ns = -1

    def close(self, reason: str, timeout_s: float = 0.5) -> Goal | None:
        """Stop taking goals, abort the running one and wait for the execute callbacks.

        The executor must keep spinning a little longer afterwards: rclpy sends the
        result to a waiting client from a follow-up executor task.

        Returns:
            The aborted goal, or None if no goal was running.
        """
        self.closing.set()
        goal = self.navigator.abort_active(reason)
        with self._idle:
            self._idle.wait_for(lambda: self._executing == 0, timeout=timeout_s)
        return goal

    def state_published(self, now_ns: int) -> None:
        """The physics loop has published the robot's state (``/tf``, odometry) at ``now_ns``."""
        with self._published:
            self._published_ns = now_ns
            self._published.notify_all()

    def wait_state_published(self, at_s: float, timeout_s: float = 5.0) -> bool:
        """Wait until the state at simulated time ``at_s`` or later has been published.

        Nav2 judges a goal done from TF, so a client never gets a result before the TF that
        shows it; waiting here before sending one keeps that order (the physics thread
        publishes at ``publish_hz``, an executor thread sends the result).

        Returns:
            Whether it was published within ``timeout_s`` wall seconds (or the gate closed).
        """
        at_ns = round(at_s * 1e9) - 1000  # finished_s is a float: allow its rounding
        with self._published:
            return self._published.wait_for(
                lambda: self._published_ns >= at_ns or self.closing.is_set(), timeout_s)

    def enter(self) -> None:
        """An execute callback starts."""
        with self._idle:
            self._executing += 1

    def leave(self) -> None:
        """An execute callback ends."""
        with self._idle:
            self._executing -= 1
            self._idle.notify_all()


@dataclass
class GoalAction:
    """How one action maps onto navigator goals.

    Attributes:
        action_type: The action type.
        start: Starts the goal for a request, or returns a failure to abort with.
        feedback: Fills a feedback message from the goal's progress.
        result: Fills result fields other than ``error_code``/``error_msg`` (optional).
    """

    action_type: Any
    start: Callable[[Any], Goal | Failure]
    feedback: Callable[[Any, Goal, Progress], None]
    result: Callable[[Any, Goal], None] | None = None


def serve_goal_action(node: Nav2LifecycleNode, name: str, gate: GoalGate, spec: GoalAction,
                      goal_callback: Callable[[Any], Any] | None = None) -> Any:
    """Create the action server ``name`` on ``node`` that runs ``spec``'s goals.

    Args:
        node: The lifecycle node (goals are refused unless it is ACTIVE).
        name: The action name.
        gate: The shared gate (shutdown, feedback rate).
        spec: What the action does.
        goal_callback: Extra checks on a request (runs only when active).

    Returns:
        The ``rclpy.action.ActionServer``.
    """

    def execute(handle: ServerGoalHandle) -> Any:
        gate.enter()
        try:
            return _run(node, gate, spec, handle)
        finally:
            gate.leave()

    return node.action_server(spec.action_type, name, execute, goal_callback)


def _run(node: Nav2LifecycleNode, gate: GoalGate, spec: GoalAction,
         handle: ServerGoalHandle) -> Any:
    result = spec.action_type.Result()
    started = spec.start(handle.request)
    if not isinstance(started, Goal):
        result.error_code, result.error_msg = started
        node.get_logger().error(f"Goal aborted: {result.error_msg}")
        handle.abort()
        return result
    goal = started
    follow_goal(gate, handle, goal, spec.action_type.Feedback(),
                lambda msg: spec.feedback(msg, goal, gate.navigator.progress(goal)))
    result.error_code = goal.error_code
    result.error_msg = goal.error_msg
    if spec.result is not None:
        spec.result(result, goal)
    elapsed = (goal.finished_s or goal.started_s) - goal.started_s
    log = node.get_logger()
    if goal.outcome is Outcome.SUCCEEDED:
        log.info(f"Goal {goal.number} ({goal.kind.value}) succeeded in {elapsed:.1f} s (sim).")
        handle.succeed()
    elif goal.outcome is Outcome.CANCELED:
        log.info(f"Goal {goal.number} canceled after {elapsed:.1f} s (sim).")
        handle.canceled()
    elif not goal.error_msg:  # preempted: routine for a replanning tree (Nav2 logs INFO)
        log.info(f"Goal {goal.number} preempted by a newer goal after {elapsed:.1f} s (sim).")
        handle.abort()
    else:
        log.warning(f"Goal {goal.number} aborted after {elapsed:.1f} s (sim): "
                    f"{goal.error_msg}")
        handle.abort()
    return result


def follow_goal(gate: GoalGate, handle: ServerGoalHandle, goal: Goal, feedback: Any,
                fill: Callable[[Any], None]) -> None:
    """Wait for ``goal`` to end, forwarding a cancel request and publishing feedback.

    Returns once the robot's state at the goal's end has been published, so the caller's
    result follows the TF that shows it.

    Args:
        gate: The shared gate (navigator, clock, feedback rate).
        handle: The action goal's handle.
        goal: The navigator goal it runs.
        feedback: The feedback message to fill and publish.
        fill: Fills ``feedback`` (called at the feedback rate).
    """
    next_feedback_ns = 0
    next_feedback_wall = 0.0
    while not goal.done.wait(POLL_PERIOD_S):
        if handle.is_cancel_requested:
            gate.navigator.cancel(goal)
            goal.done.wait()  # set by cancel(), or by a concurrent end
            break
        now_ns, wall = gate.now_ns(), time.monotonic()
        if now_ns >= next_feedback_ns and wall >= next_feedback_wall:
            fill(feedback)
            handle.publish_feedback(feedback)
            next_feedback_ns = now_ns + round(gate.feedback_period_s * 1e9)
            next_feedback_wall = wall + 1.0 / MAX_FEEDBACK_WALL_HZ
    gate.wait_state_published(goal.finished_s or goal.started_s)


def elapsed_msg(goal: Goal) -> Any:
    """``builtin_interfaces/Duration`` from the goal's start to its end."""
    return duration_msg((goal.finished_s or goal.started_s) - goal.started_s)
