"""Nav2ServiceLeaf: the base of the Nav2 service nodes (Nav2's ``BtServiceNode``), asynchronous.

The first tick of an active period fills the request (:meth:`Nav2ServiceLeaf.on_tick`)
and sends it once the service is there (within the navigator's
``wait_for_service_timeout``); later ticks poll the future. A response that has not
arrived by a tick ``server_timeout`` (ms; the navigator's ``default_server_timeout``,
20 ms, when unbound) after the call fails the leaf, as Nav2's "Node timed out while
executing service call"; a response -> :meth:`on_completion` (SUCCESS). The service is
the ``service_name`` port (Nav2's service nodes have no default name).
"""

from __future__ import annotations

import importlib
import time
from typing import Any

from py_trees.common import Status

from .._ros_leaf import RosLeaf
from ._common import optional_input, server_missing, server_timeout_s


class Nav2ServiceLeaf(RosLeaf):
    """A client of one Nav2 service; subclasses fill the request and read the response.

    Class attributes:
        SERVICE: ``(module, type)`` of the service.
        SERVER: The service name used without a ``service_name`` port ("": none).

    Args:
        name: The behaviour's name.
        ports: The leaf's ports (``service_name``, ``server_timeout`` and its own).
    """

    SERVICE: tuple[str, str] = ("", "")
    SERVER = ""

    def __init__(self, name: str, *, ports: Any) -> None:
        super().__init__(name)
        self.ports = ports
        self.service_name = self.SERVER
        self.request: Any = None
        self.response: Any = None
        self._type: Any = None
        self._client: Any = None
        self._future: Any = None
        self._started = 0.0
        self._sent = 0.0

    def on_tick(self) -> bool:
        """Fill ``self.request`` from the ports; return False to fail without calling."""
        return True

    def on_completion(self) -> Status:
        """The response arrived (``self.response``)."""
        return Status.SUCCESS

    def setup(self, **kwargs: Any) -> None:
        """Take the ROS node and create the client of ``service_name``.

        Args:
            **kwargs: Must hold ``node``.
        """
        super().setup(**kwargs)
        module, type_name = self.SERVICE
        self._type = getattr(importlib.import_module(module), type_name)
        self.service_name = optional_input(self.ports, "service_name", self.SERVER) or ""
        if self.service_name:
            self._client = self.node.create_client(self._type, self.service_name)

    def initialise(self) -> None:
        """Start an active period: fill the request, call when the service is there."""
        self._reset_latch()
        self._future = self.response = None
        self._started = time.monotonic()
        if self._client is None:
            self._latch(False, f"{self.name}: no service_name given")
            return
        self.request = self._type.Request()
        if not self.on_tick():
            self._latch(False, self.feedback_message or f"{self.name}: no request to send")
            return
        if self._client.service_is_ready():
            self._call()
        else:
            self.feedback_message = f"waiting for the {self.service_name} service"

    def update(self) -> Status:
        """Poll without blocking; RUNNING until the response, then the latched verdict."""
        if self._done:
            return self._verdict()
        now = time.monotonic()
        if self._future is None:
            if self._client.service_is_ready():
                self._call()
                return Status.RUNNING
            missing = server_missing(self._node, self._started, now,
                                     f"\"{self.service_name}\" service server")
            if missing is not None:
                return self._latch(False, missing)
            return Status.RUNNING
        if not self._future.done():
            if now - self._sent < server_timeout_s(self._node, self.ports):
                return Status.RUNNING
            self._future.cancel()
            self._future = None
            return self._latch(False, "Node timed out while executing service call to "
                                      f"{self.service_name}.")
        future, self._future = self._future, None
        if future.exception() is not None:
            return self._latch(False, f"{self.service_name} failed: {future.exception()}")
        self.response = future.result()
        verdict = self.on_completion()
        # a success is not logged, as Nav2's BT nodes say nothing then (rclpy's logger finds
        # its caller's source file on every call: milliseconds inside the 10 ms tick)
        return self._latch(verdict == Status.SUCCESS, f"{self.service_name} answered",
                           log=verdict != Status.SUCCESS)

    def terminate(self, new_status: Status) -> None:
        """On a halt, forget the call in flight (a service call cannot be cancelled)."""
        if self._future is not None and not self._done:
            self._future.cancel()
            self._future = None

    def shutdown(self) -> None:
        """Destroy the client."""
        if self._client is not None:
            self.node.destroy_client(self._client)
            self._client = None

    def _call(self) -> None:
        self._future = self._client.call_async(self.request)
        self._sent = time.monotonic()
        self.feedback_message = f"called {self.service_name}"
