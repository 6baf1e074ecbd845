"""In-process rclpy helpers: an isolated context, a node, and bounded spinning.

Tests drive behaviours the way the runner does: one thread, an executor, and ticks
interleaved with ``spin_once``; nothing blocks on a future.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any


@contextmanager
def ros_node(name: str, **node_kwargs: Any) -> Iterator[tuple[Any, Any]]:
    """Yield ``(node, executor)`` on a fresh rclpy context, torn down afterwards.

    Args:
        name: The node name.
        **node_kwargs: Passed to ``rclpy.node.Node``.
    """
    import rclpy
    from rclpy.context import Context
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.node import Node

    context = Context()
    rclpy.init(context=context)
    node = Node(name, context=context, **node_kwargs)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    try:
        yield node, executor
    finally:
        executor.shutdown()
        node.destroy_node()
        rclpy.shutdown(context=context)


def spin_until(executor: Any, predicate: Callable[[], bool], timeout: float,
               step: Callable[[], None] | None = None) -> bool:
    """Spin until ``predicate()`` is true or ``timeout`` seconds pass.

    Args:
        executor: An rclpy executor.
        predicate: Checked after each spin.
        timeout: Seconds.
        step: Called after each spin (e.g. a tree tick).

    Returns:
        Whether the predicate became true.
    """
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.02)
        if step is not None:
            step()
        if predicate():
            return True
    return predicate()
