"""Real ROS servers for the toolkit's tests, spun on a thread of their own.

The server node shares the test node's context (fast discovery) but has its own
multi-threaded executor on a background thread, so a server that takes its time (a slow
acceptance, a goal that runs until cancelled) never blocks the test's ticks. When a test ends,
its server ends the goals still executing before the node is destroyed: an execute callback
never outlives the action server it publishes through.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any


@dataclass
class WaitServerLog:
    """What a test's ``nav2_msgs/action/Wait`` server saw and how it answers.

    Attributes:
        accept_delay_wall_s: Wall seconds the server takes to accept each goal.
        outcome: ``succeed``, ``abort`` or ``hang`` (run until cancelled).
        goals: The goals it received (their ``time.sec``).
        cancels: How many cancel requests it received.
        feedback_steps: Feedback messages published before the outcome.
    """

    accept_delay_wall_s: float = 0.0
    outcome: str = "succeed"
    goals: list[int] = field(default_factory=list)
    cancels: int = 0
    feedback_steps: int = 2


class GoalsInFlight:
    """The execute callbacks still running on a server node, and the order to end them."""

    def __init__(self) -> None:
        self.closing = threading.Event()
        self._running = 0
        self._changed = threading.Condition()

    @contextmanager
    def running(self) -> Iterator[None]:
        """Count one execute callback while its body runs."""
        with self._changed:
            self._running += 1
        try:
            yield
        finally:
            with self._changed:
                self._running -= 1
                self._changed.notify_all()

    def end_all(self, outer_s: float) -> None:
        """Tell every execute callback to end its goal and wait until none runs."""
        self.closing.set()
        with self._changed:
            ended = self._changed.wait_for(lambda: self._running == 0, outer_s)
        assert ended, f"{self._running} test goal(s) still executing after {outer_s} s"


@contextmanager
def server_thread(node: Any) -> Iterator[Any]:
    """Yield a server node in ``node``'s context, spun on a background thread."""
    from rclpy.executors import MultiThreadedExecutor
    from rclpy.node import Node

    server = Node("toolkit_test_server", context=node.context)
    server.goals_in_flight = GoalsInFlight()  # serve_wait's execute callbacks report to it
    executor = MultiThreadedExecutor(num_threads=3, context=node.context)
    executor.add_node(server)
    thread = threading.Thread(target=executor.spin, daemon=True)
    thread.start()
    try:
        yield server
    finally:
        server.goals_in_flight.end_all(10.0)  # outer safety bound
        executor.shutdown()
        thread.join(timeout=10.0)  # outer safety bound
        server.destroy_node()


def serve_wait(server: Any, name: str, log: WaitServerLog) -> Any:
    """Offer a ``nav2_msgs/action/Wait`` action called ``name`` that answers per ``log``."""
    from nav2_msgs.action import Wait
    from rclpy.action import ActionServer, CancelResponse, GoalResponse
    from rclpy.callback_groups import ReentrantCallbackGroup

    def on_goal(goal: Any) -> Any:
        log.goals.append(int(goal.time.sec))
        time.sleep(log.accept_delay_wall_s)
        return GoalResponse.ACCEPT

    def on_cancel(_handle: Any) -> Any:
        log.cancels += 1
        return CancelResponse.ACCEPT

    in_flight: GoalsInFlight = server.goals_in_flight
    closing = in_flight.closing

    def execute(handle: Any) -> Any:
        with in_flight.running():
            return run(handle)

    def run(handle: Any) -> Any:
        result = Wait.Result()
        for step in range(log.feedback_steps):
            if closing.is_set():  # the test is over: end the goal, publish nothing more
                handle.abort()
                return result
            feedback = Wait.Feedback()
            feedback.time_left.sec = log.feedback_steps - step
            handle.publish_feedback(feedback)
            closing.wait(0.05)
        if log.outcome == "hang":
            # until the test cancels or ends; the 30 s are only an outer safety bound
            deadline = time.monotonic() + 30.0
            while not (handle.is_cancel_requested or closing.is_set()):
                if time.monotonic() > deadline:  # outer safety bound
                    break
                closing.wait(0.02)
            if handle.is_cancel_requested:
                handle.canceled()
            else:
                handle.abort()
            return result
        if log.outcome == "abort":
            result.error_code, result.error_msg = 7, "blocked"
            handle.abort()
            return result
        handle.succeed()
        return result

    return ActionServer(server, Wait, name, execute_callback=execute, goal_callback=on_goal,
                        cancel_callback=on_cancel, callback_group=ReentrantCallbackGroup())
