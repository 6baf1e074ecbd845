"""ServiceLeaf: the base of leaves that make one polled service request per activation.

The shared life cycle behind DetectSurvivor and NotifyBase: ``setup()`` creates a
:class:`~._service_call.PolledServiceCall`, ``initialise()`` resets the latch and starts a
request period, ``update()`` polls without blocking (``waiting for <service>`` until the
server is ready), ``terminate()`` abandons an unanswered request and ``shutdown()`` destroys
the client. A subclass only says which service type it calls (:meth:`ServiceLeaf._srv`),
what it asks (:meth:`ServiceLeaf._request`), what it says while waiting for the answer
(:meth:`ServiceLeaf._awaiting`) and its verdict on the answer (:meth:`ServiceLeaf._verdict_on`).

Not a plugin itself (it carries no ``@leaf`` mark), and it imports no ROS package.
"""

from __future__ import annotations

from typing import Any

from py_trees.common import Status

from sar_framework.engine.plugin import Param

from ._ros_leaf import RosLeaf
from ._service_call import PolledServiceCall

#: The bounds every service leaf declares, after its own params.
SERVICE_TIMEOUT_PARAMS: tuple[Param, ...] = (
    Param("server_timeout_s", float, default=10.0, exclusive_minimum=0.0,
          description="Fail if the service is not ready within this many seconds (ROS time)."),
    Param("response_timeout_s", float, default=10.0, exclusive_minimum=0.0,
          description="Fail if the service has not answered this many seconds after "
                      "the request (ROS time)."),
)


class ServiceLeaf(RosLeaf):
    """Base of the service leaves; subclasses say what to ask and what the answer means.

    Args:
        name: The behaviour's name.
        service_name: The service to call.
        server_timeout_s: Bound on waiting for the service.
        response_timeout_s: Bound on waiting for the answer.
    """

    def __init__(self, name: str, *, service_name: str, server_timeout_s: float,
                 response_timeout_s: float) -> None:
        super().__init__(name)
        self.service_name = service_name
        self.server_timeout_s = server_timeout_s
        self.response_timeout_s = response_timeout_s
        self._call: PolledServiceCall | None = None
        self._srv_type: Any = None

    # -- what a subclass says --------------------------------------------------------------

    def _srv(self) -> Any:
        """Import (lazily) and return the service type."""
        raise NotImplementedError

    def _request(self) -> Any:
        """Build the request; called once per activation, when the server is ready."""
        raise NotImplementedError

    def _awaiting(self) -> str:
        """Return the feedback message while the request waits for its answer."""
        raise NotImplementedError

    def _verdict_on(self, response: Any) -> Status:
        """Latch and return the verdict on the service's response."""
        raise NotImplementedError

    # -- the shared life cycle -------------------------------------------------------------

    def setup(self, **kwargs: Any) -> None:
        """Take the ROS node and create the service client.

        Args:
            **kwargs: Must hold ``node``.
        """
        super().setup(**kwargs)
        self._srv_type = self._srv()
        self._call = PolledServiceCall(
            self.node, self._srv_type, self.service_name,
            server_timeout_s=self.server_timeout_s, response_timeout_s=self.response_timeout_s,
        )

    def initialise(self) -> None:
        """Reset the latch and start a new request period."""
        self._reset_latch()
        self._service().start()

    def update(self) -> Status:
        """Poll the request.

        Returns:
            RUNNING until the answer; the subclass's verdict on it; FAILURE on a bound or a
            failed call.
        """
        if self._done:
            return self._verdict()
        result = self._service().poll(self._request)
        if result is None:
            self.feedback_message = (f"waiting for {self.service_name}"
                                     if self._service().waiting_for_server()
                                     else self._awaiting())
            return Status.RUNNING
        if result.error is not None:
            return self._latch(False, result.error)
        return self._verdict_on(result.response)

    def terminate(self, new_status: Status) -> None:
        """Drop a request still waiting for its answer when halted.

        Args:
            new_status: The status the leaf is moving to.
        """
        if not self._done and self._call is not None:
            self._call.abandon()

    def shutdown(self) -> None:
        """Destroy the service client."""
        if self._call is not None:
            self._call.destroy()
            self._call = None

    def _service(self) -> PolledServiceCall:
        if self._call is None:
            raise RuntimeError(f"{type(self).__name__} '{self.name}' used before setup(node=...)")
        return self._call
