"""Nav2's IsPathValid: ask the planner server whether ``path`` is still collision-free.

A condition answers in the tick it is ticked, so, as Nav2's does, it waits for the answer
of the ``is_path_valid`` service for at most ``server_timeout`` (the navigator's
``default_server_timeout``, 20 ms, when unbound). Nav2 spins a callback group of its own
for that; here the client lives on a private node spun by a private executor, so the
tree's executor is never spun from inside its own tick.
"""

from __future__ import annotations

import itertools
from typing import Any

from py_trees.common import Status

from sar_framework.engine.plugin import leaf
from sar_framework.engine.ports import InputPort

from ._common import optional_input, server_timeout_s, timeout_port, wait_for_service_s
from .conditions import Nav2Condition

_serial = itertools.count()


@leaf(condition=True, ports=[
    InputPort("path", "nav_msgs/msg/Path", optional=True,
              description="The global path to check for validity."),
    timeout_port(),
])
class IsPathValid(Nav2Condition):
    """Nav2's IsPathValid: SUCCESS when ``is_path_valid`` says the path is valid."""

    SERVICE = "is_path_valid"

    def __init__(self, name: str, *, ports: Any) -> None:
        super().__init__(name, ports=ports)
        self._private: Any = None
        self._executor: Any = None
        self._client: Any = None

    def setup(self, **kwargs: Any) -> None:
        """Make the private node, executor and client; wait for the service a while."""
        super().setup(**kwargs)
        if self.node is None or self._client is not None:
            return
        import rclpy
        from nav2_msgs.srv import IsPathValid as Service
        from rclpy.executors import SingleThreadedExecutor

        context = self.node.context
        self._private = rclpy.create_node(
            f"{self.node.get_name()}_is_path_valid_{next(_serial)}",
            namespace=self.node.get_namespace(), context=context)
        self._executor = SingleThreadedExecutor(context=context)
        self._executor.add_node(self._private)
        self._client = self._private.create_client(Service, self.SERVICE)
        self._client.wait_for_service(timeout_sec=wait_for_service_s(self.node))

    def update(self) -> Status:
        """Ask and wait up to ``server_timeout``; FAILURE when invalid or unanswered."""
        path = optional_input(self.ports, "path")
        if self._client is None or path is None:
            self.feedback_message = "no path" if path is None else "not set up with a node"
            return Status.FAILURE
        request = self._client.srv_type.Request()
        request.path = path
        future = self._client.call_async(request)
        self._executor.spin_until_future_complete(
            future, timeout_sec=server_timeout_s(self.node, self.ports))
        if not future.done():
            future.cancel()
            self.feedback_message = f"{self.SERVICE}: no answer in time"
            return Status.FAILURE
        valid = bool(future.result().is_valid)
        self.feedback_message = "path valid" if valid else "path invalid"
        return Status.SUCCESS if valid else Status.FAILURE

    def shutdown(self) -> None:
        """Destroy the private node and executor."""
        if self._private is not None:
            self._executor.shutdown()
            self._private.destroy_node()
            self._private = self._executor = self._client = None
