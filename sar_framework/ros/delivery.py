"""Before a node exits: let the subscribers it knows of receive what it published.

A short mission can end, and its runner exit, before a recorder or watcher that was
already listening has matched the runner's publishers (discovery takes a while on a busy
machine). Transient-local history only reaches a subscriber while the publisher lives, so
the runner waits, within a bound, until each of its publishers on the given topics has
matched every subscription the ROS graph shows, and until those have acknowledged
everything published (``Publisher.wait_for_all_acked``).
"""

from __future__ import annotations

import time
from collections.abc import Iterable
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from rclpy.executors import Executor
    from rclpy.node import Node


def deliver(node: Node, executor: Executor, topics: Iterable[str], bound_wall_s: float) -> bool:
    """Wait until every subscriber of ``topics`` matched and acknowledged ``node``'s messages.

    Args:
        node: The publishing node.
        executor: The executor ``node`` is spun by (spun while waiting for matches).
        topics: Fully qualified topic names of ``node``'s publishers to deliver.
        bound_wall_s: Wall seconds at most, in all.

    Returns:
        Whether everything was delivered within the bound.
    """
    from rclpy.duration import Duration

    wanted = set(topics)
    publishers = [p for p in node.publishers if p.topic_name in wanted]
    deadline = time.monotonic() + bound_wall_s

    def matched() -> bool:
        return all(p.get_subscription_count() >= node.count_subscribers(p.topic_name)
                   for p in publishers)

    while not matched():
        if time.monotonic() >= deadline:
            return False
        executor.spin_once(timeout_sec=0.05)
    for publisher in publishers:
        left = max(0.0, deadline - time.monotonic())
        if not publisher.wait_for_all_acked(Duration(nanoseconds=int(left * 1e9))):
            return False
    return True
