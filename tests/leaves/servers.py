"""Real ROS servers for the toolkit's tests, spun on a thread of their own.

The server node shares the test node's context (fast discovery) but has its own
multi-threaded executor on a background thread, so a server that takes its time (a slow
acceptance, a goal that runs until cancelled) never blocks the test's ticks.
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


@contextmanager
def server_thread(node: Any) -> Iterator[Any]:
    """Yield a server node in ``node``'s context, spun on a background thread."""
    from rclpy.executors import MultiThreadedExecutor
    from rclpy.node import Node

    server = Node("toolkit_test_server", context=node.context)
    executor = MultiThreadedExecutor(num_threads=3, context=node.context)
    executor.add_node(server)
    thread = threading.Thread(target=executor.spin, daemon=True)
    thread.start()
    try:
        yield server
    finally:
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

    def execute(handle: Any) -> Any:
        result = Wait.Result()
        for step in range(log.feedback_steps):
            feedback = Wait.Feedback()
            feedback.time_left.sec = log.feedback_steps - step
            handle.publish_feedback(feedback)
            time.sleep(0.05)
        if log.outcome == "hang":
            deadline = time.monotonic() + 30.0  # a test's cancel ends the goal before
            cancelled = handle.is_cancel_requested
            while not cancelled and time.monotonic() < deadline:  # outer safety bound
                time.sleep(0.02)
                cancelled = handle.is_cancel_requested
            handle.canceled()
            return result
        if log.outcome == "abort":
            result.error_code, result.error_msg = 7, "blocked"
            handle.abort()
            return result
        handle.succeed()
        return result

    return ActionServer(server, Wait, name, execute_callback=execute, goal_callback=on_goal,
                        cancel_callback=on_cancel, callback_group=ReentrantCallbackGroup())
