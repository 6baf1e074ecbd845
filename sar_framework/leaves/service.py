"""ServiceLeaf: one ROS service request per activation, polled by tick, never blocking.

The course guide's async-poll pattern (``service_is_ready``, ``call_async`` once, poll the
future), on the semantics of BehaviorTree.ROS2's ``RosServiceNode``: a subclass fills the
request in one method (:meth:`ServiceLeaf.set_request`, from its params and ports) and reads
the answer in another (:meth:`ServiceLeaf.on_response`); whatever goes wrong on the way
(no server, no answer, a failed call, a refused request) reaches
:meth:`ServiceLeaf.on_failure` with the reason, which also becomes ``feedback_message``.

Both bounds count on the node's clock (ROS time: simulated seconds with ``use_sim_time``):
``server_timeout_s`` from the first tick until the service is ready, ``response_timeout_s``
from the request until its answer (:class:`~.service_call.PolledServiceCall`). A halt drops an
unanswered request (a service call cannot be cancelled). Imports no ROS package at import.
"""

from __future__ import annotations

from typing import Any, ClassVar

from py_trees.common import Status

from sar_framework.engine.param import Param
from sar_framework.leaves.declared import interface_type
from sar_framework.leaves.ros_leaf import RosLeaf
from sar_framework.leaves.service_call import PolledServiceCall


def service_params(service_name: str, *, server_timeout_s: float = 10.0,
                   response_timeout_s: float = 10.0) -> tuple[Param, ...]:
    """The params a :class:`ServiceLeaf` reads: the service's name and the two bounds.

    Declare them in the leaf's ``@leaf(params=[...])``; a tree may then set each.

    Args:
        service_name: The default service name (relative names resolve in the node's
            namespace).
        server_timeout_s: The default bound on waiting for the service (ROS seconds).
        response_timeout_s: The default bound on waiting for the answer (ROS seconds).

    Returns:
        ``service_name``, ``server_timeout_s`` and ``response_timeout_s``.
    """
    return (
        Param("service_name", str, default=service_name,
              description="The service to call."),
        *service_timeout_params(server_timeout_s, response_timeout_s),
    )


def service_timeout_params(server_timeout_s: float = 10.0,
                           response_timeout_s: float = 10.0) -> tuple[Param, ...]:
    """The two bounds alone: ``server_timeout_s`` and ``response_timeout_s`` (ROS seconds)."""
    return (
        Param("server_timeout_s", float, default=server_timeout_s, exclusive_minimum=0.0,
              description="Fail if the service is not ready within this many seconds "
                          "(ROS time)."),
        Param("response_timeout_s", float, default=response_timeout_s, exclusive_minimum=0.0,
              description="Fail if the service has not answered this many seconds after "
                          "the request (ROS time)."),
    )


class ServiceLeaf(RosLeaf):
    """A client of one ROS service: one request per activation, polled by tick.

    Set :attr:`service_type`; declare :func:`service_params` (or set ``service_name``,
    ``server_timeout_s`` and ``response_timeout_s`` otherwise); override
    :meth:`set_request` and :meth:`on_response`.

    Example::

        @leaf(params=[*service_params("trigger")])
        class Trigger(ServiceLeaf):
            service_type = "std_srvs/srv/Trigger"

            def on_response(self, response):
                if response.success:
                    return self.succeed(response.message)
                return self.fail(response.message)

    Args:
        name: The behaviour's name.
        **declared: The declared params (``service_name``, ``server_timeout_s``,
            ``response_timeout_s`` and the leaf's own), context objects and ``ports``.
    """

    #: The service type as ``ros2 interface`` names it (``std_srvs/srv/Trigger``).
    service_type: ClassVar[str] = ""
    #: Whether a request still unanswered after two wall seconds may be sent again (the
    #: first answer wins): true only for a service whose requests are safe to repeat.
    idempotent: ClassVar[bool] = True

    def __init__(self, name: str, **declared: Any) -> None:
        self.service_name: str = ""
        self.server_timeout_s: float = 10.0
        self.response_timeout_s: float = 10.0
        self.response_timeout_wall_s: float | None = None
        super().__init__(name, **declared)
        self.request: Any = None
        self._call: PolledServiceCall | None = None
        self._srv: Any = None

    # -- what a subclass says -------------------------------------------------------------

    def set_request(self, request: Any) -> bool | None:
        """Fill ``request`` (a fresh ``Request``) once the service is ready.

        Args:
            request: The request to fill.

        Returns:
            False to fail without calling (say why in ``feedback_message``); None or True
            to send it.
        """
        return None

    def on_response(self, response: Any) -> Status:
        """Judge the answer; the default succeeds.

        Args:
            response: The service's response.

        Returns:
            The leaf's verdict, usually through :meth:`~sar_framework.leaves.RosLeaf.succeed` or
            :meth:`~sar_framework.leaves.RosLeaf.fail`.
        """
        return self.succeed(f"{self.service_name} answered", log=False)

    def on_failure(self, reason: str) -> Status:
        """Judge a request that got no answer (no server, a bound, a failed call).

        Args:
            reason: What went wrong, e.g. ``/trigger service not available after 1.0 s``.

        Returns:
            The leaf's verdict; FAILURE by default.
        """
        return self.fail(reason)

    def waiting_message(self) -> str:
        """The ``feedback_message`` while the request waits for its answer."""
        return f"called {self.service_name}"

    # -- the life cycle -------------------------------------------------------------------

    def setup(self, **kwargs: Any) -> None:
        """Take the ROS node and create the service client.

        Args:
            **kwargs: Must hold ``node``; may hold ``events``.
        """
        super().setup(**kwargs)
        self._srv = interface_type(self.service_type)
        self._call = PolledServiceCall(
            self.node, self._srv, self.service_name,
            server_timeout_s=self.server_timeout_s, response_timeout_s=self.response_timeout_s,
            resend_after_wall_s=2.0 if self.idempotent else None,
            response_timeout_wall_s=self.response_timeout_wall_s,
        )

    def initialise(self) -> None:
        """Forget the last verdict and start a new request period."""
        self.reset_latch()
        self.request = None
        self._service().start()

    def update(self) -> Status:
        """Poll the request without blocking.

        Returns:
            RUNNING until the answer, then the latched verdict.
        """
        if self._done:
            return self.verdict()
        result = self._service().poll(self._make_request)
        if self._done:  # set_request refused
            return self.verdict()
        if result is None:
            self.feedback_message = (f"waiting for {self._service().service_name}"
                                     if self._service().waiting_for_server()
                                     else self.waiting_message())
            return Status.RUNNING
        if result.error is not None:
            return self.on_failure(result.error)
        return self.on_response(result.response)

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

    def _make_request(self) -> Any:
        request = self._srv.Request()
        if self.set_request(request) is False:
            self.fail(self.feedback_message or f"{self.name}: no request to send")
            return None
        self.request = request
        return request

    def _service(self) -> PolledServiceCall:
        if self._call is None:
            raise RuntimeError(f"{type(self).__name__} '{self.name}' used before setup(node=...)")
        return self._call
