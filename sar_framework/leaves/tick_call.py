"""TickServiceCall: a service call answered inside one tick, for a condition.

A condition answers in the tick it is ticked, so a condition that asks a service (Nav2's
IsPathValid) must wait for the answer there, for a short wall-clock bound. Nav2 spins a
callback group of its own for that; here the client lives on a private node spun by a
private executor, so the tree's own executor is never spun from inside its own tick. Prefer
:class:`~.service.ServiceLeaf` (RUNNING while it waits) whenever the leaf may be an action.
"""

from __future__ import annotations

import itertools
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from rclpy.node import Node

_serial = itertools.count()


class TickServiceCall:
    """A client on a private node whose calls block for at most a wall-clock bound.

    Args:
        node: The tree's node (its context, name and namespace are used).
        srv_type: The service type.
        service_name: The service (relative: in the node's namespace).
        wait_for_server_wall_s: Wall seconds to wait for the service when made.
    """

    def __init__(self, node: Node, srv_type: Any, service_name: str, *,
                 wait_for_server_wall_s: float) -> None:
        import rclpy
        from rclpy.executors import SingleThreadedExecutor

        self.service_name = service_name
        self._type = srv_type
        self._private = rclpy.create_node(
            f"{node.get_name()}_{service_name.strip('/').replace('/', '_')}_{next(_serial)}",
            namespace=node.get_namespace(), context=node.context)
        self._executor = SingleThreadedExecutor(context=node.context)
        self._executor.add_node(self._private)
        self._client = self._private.create_client(srv_type, service_name)
        self._client.wait_for_service(timeout_sec=wait_for_server_wall_s)

    def request(self) -> Any:
        """A fresh request of the service's type."""
        return self._type.Request()

    def call(self, request: Any, *, timeout_wall_s: float) -> Any:
        """Send ``request`` and wait for the answer.

        Args:
            request: The request.
            timeout_wall_s: Wall seconds to wait.

        Returns:
            The response, or None when none came in time.
        """
        future = self._client.call_async(request)
        self._executor.spin_until_future_complete(future, timeout_sec=timeout_wall_s)
        if not future.done():
            future.cancel()
            return None
        return future.result()

    def destroy(self) -> None:
        """Destroy the private node and executor."""
        self._executor.shutdown()
        self._private.destroy_node()
