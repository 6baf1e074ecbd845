"""In-process rclpy helpers: an isolated context, a node, and bounded spinning.

Tests drive behaviours the way the runner does: one thread, an executor, and ticks
interleaved with ``spin_once``; nothing blocks on a future.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

DISCOVERY_S = 15.0


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
        # destroy_node() leaves action clients and servers, which keep the node (and the
        # context's DDS participant) alive in the graph until garbage collection: a later
        # test on the same domain would see them
        for waitable in list(node.waitables):
            if hasattr(waitable, "destroy"):
                waitable.destroy()
        node.destroy_node()
        rclpy.shutdown(context=context)


def spin_until(executor: Any, predicate: Callable[[], bool], timeout: float,
               step: Callable[[], None] | None = None) -> bool:
    """Spin until ``predicate()`` is true or ``timeout`` seconds pass.

    Args:
        executor: An rclpy executor.
        predicate: Checked after each spin.
        timeout: Seconds: an outer safety bound (the caller asserts the result, naming what
            it awaited), never a figure under test.
        step: Called after each spin (e.g. a tree tick).

    Returns:
        Whether the predicate became true.
    """
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:  # outer safety bound
        executor.spin_once(timeout_sec=0.02)
        if step is not None:
            step()
        if predicate():
            return True
    return predicate()


def call_service(node: Any, executor: Any, srv_type: Any, name: str, request: Any, *,
                 timeout: float = 10.0, resend_after: float | None = 2.0,
                 discovery_timeout: float = DISCOVERY_S) -> Any:
    """Call a service from a test: wait for the server, send, spin until the first answer.

    DDS can drop the reply to a request sent just after discovery (``service_is_ready``
    proves only the request path), most often on a loaded machine. An idempotent request is
    therefore sent again every ``resend_after`` seconds while unanswered; the first answer
    wins. Pass ``resend_after=None`` for a request that must not be repeated (a lifecycle
    transition).

    Args:
        node: The calling node.
        executor: The executor spinning ``node``.
        srv_type: The service type.
        name: The service name.
        request: The request.
        timeout: Seconds the answer may take, from the first send.
        resend_after: Seconds between sends while unanswered, or None for a single send.
        discovery_timeout: Seconds the server may take to appear.

    Returns:
        The response.

    Raises:
        AssertionError: The server did not appear, or nothing answered in time.
    """
    client = node.create_client(srv_type, name)
    try:
        assert spin_until(executor, client.service_is_ready, discovery_timeout), (
            f"{name}: no server after {discovery_timeout:.0f} s")
        futures = [client.call_async(request)]

        def answered() -> bool:
            return any(future.done() for future in futures)

        waits = [timeout]
        if resend_after is not None:
            again = max(1, math.ceil(timeout / resend_after)) - 1
            waits = [resend_after] * again + [timeout - resend_after * again]
        for index, wait_s in enumerate(waits):
            if index:  # a request lost in transport is sent again
                futures.append(client.call_async(request))
            if spin_until(executor, answered, wait_s):
                break
        assert answered(), (
            f"{name}: no answer within {timeout:.0f} s ({len(futures)} sends)")
        return next(future for future in futures if future.done()).result()
    finally:
        node.destroy_client(client)
