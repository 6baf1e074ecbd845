"""Nav2's IsPathValid: ask the planner server whether ``path`` is still collision-free.

A condition answers in the tick it is ticked, so, as Nav2's does, it waits for the answer
of the ``is_path_valid`` service for at most ``server_timeout`` (the navigator's
``default_server_timeout``, 20 ms, when unbound): the toolkit's
:class:`~sar_framework.leaves.TickServiceCall`.
"""

from __future__ import annotations

from typing import Any

from py_trees.common import Status

from sar_framework.engine.plugin import leaf
from sar_framework.engine.ports import InputPort
from sar_framework.leaves import TickServiceCall, interface_type

from ._common import optional_input, server_timeout_s, timeout_port, wait_for_service_s
from .conditions import Nav2Condition


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
        self._call: TickServiceCall | None = None

    def setup(self, **kwargs: Any) -> None:
        """Make the in-tick client; wait for the service a while."""
        super().setup(**kwargs)
        if self.node is None or self._call is not None:
            return
        self._call = TickServiceCall(self.node, interface_type("nav2_msgs/srv/IsPathValid"),
                                     self.SERVICE,
                                     wait_for_server_wall_s=wait_for_service_s(self.node))

    def update(self) -> Status:
        """Ask and wait up to ``server_timeout``; FAILURE when invalid or unanswered."""
        path = optional_input(self.ports, "path")
        if self._call is None or path is None:
            self.feedback_message = "no path" if path is None else "not set up with a node"
            return Status.FAILURE
        request = self._call.request()
        request.path = path
        response = self._call.call(request,
                                   timeout_wall_s=server_timeout_s(self.node, self.ports))
        if response is None:
            self.feedback_message = f"{self.SERVICE}: no answer in time"
            return Status.FAILURE
        valid = bool(response.is_valid)
        self.feedback_message = "path valid" if valid else "path invalid"
        return Status.SUCCESS if valid else Status.FAILURE

    def shutdown(self) -> None:
        """Destroy the in-tick client."""
        if self._call is not None:
            self._call.destroy()
            self._call = None
