"""PolledServiceCall: one bounded, non-blocking ROS service request, polled by tick.

The guide's async-poll pattern (``service_is_ready``, ``call_async`` once, poll the
future) with two bounds so nothing waits forever: the server must be ready within
``server_timeout_s`` of :meth:`PolledServiceCall.start` and must answer within
``response_timeout_s`` of the request. Both bounds count on the node's clock (ROS time:
simulated seconds with ``use_sim_time``), like every duration a tree declares. Only the
resend interval, ``resend_after_wall_s``, is wall time: it protects against a request lost
in transport, whatever the simulation's speed.

A request still unanswered after ``resend_after_wall_s`` is sent once more, and again at that
interval, keeping the earlier ones pending: the first answer to any of them wins. DDS can
lose the reply to a request sent just after discovery, because ``service_is_ready()``
proves only the request path, not that the server has matched the client's reply reader
(ros2/rmw_cyclonedds#74); a slow server's first answer still counts. Resend only to an
idempotent service (a detection is a lookup; a repeated report is acknowledged but recorded
once); ``resend_after_wall_s=None`` sends once. ``response_timeout_s`` still counts from the
first send. Like every bound on an answer, ``response_timeout_s`` fails a request only once it
had already passed at an earlier poll (:class:`~.second_look.SecondLook`): one slow tick alone
never fails a call whose answer waits for the executor's turn. A call that may be resent fails
on it only once its first resend went out at an earlier poll: at a high speed the bound's
simulated seconds are a fraction of a wall second, too short for a loaded or just-started
server to answer or for the resend to recover a lost reply, so the resend interval is its
floor (at 1x the resend comes before the bound anyway). ``server_timeout_s`` has no floor: a
server that is not there loses no reply, and its bound fires after its simulated seconds.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from sar_framework.leaves.second_look import SecondLook

if TYPE_CHECKING:
    from rclpy.node import Node
    from rclpy.task import Future


@dataclass(frozen=True)
class CallResult:
    """The end of one request: a response or the reason there is none.

    Attributes:
        response: The service's response (None on error).
        error: Why there is no response (None on success).
    """

    response: Any = None
    error: str | None = None


class PolledServiceCall:
    """A service client that makes one request per :meth:`start` and never blocks.

    Args:
        node: The node that owns the client.
        srv_type: The service type (e.g. ``std_srvs.srv.Trigger``).
        service_name: The service to call (relative: in the node's namespace; messages
            name it fully resolved).
        server_timeout_s: Seconds the server may take to become ready.
        response_timeout_s: Seconds the server may take to answer a request.
        resend_after_wall_s: Wall seconds without an answer after which the request is sent
            again (None: never); ``response_timeout_s`` then fails the call only after the
            first resend had a poll to be answered.
        response_timeout_wall_s: A bound on the answer in wall seconds too (None: none),
            for a round trip that is transport, not work (Nav2's ``server_timeout``). Like
            :class:`~.goal_call.PolledGoal`'s acceptance bound, it fails a request only once
            it had already passed at an earlier poll.
    """

    def __init__(self, node: Node, srv_type: Any, service_name: str, *,
                 server_timeout_s: float, response_timeout_s: float,
                 resend_after_wall_s: float | None = 2.0,
                 response_timeout_wall_s: float | None = None) -> None:
        self._node = node
        self._client = node.create_client(srv_type, service_name)
        self.service_name: str = self._client.service_name  # resolved: /robot1/scan_shelf
        self._server_timeout_s = server_timeout_s
        self._response_timeout_s = response_timeout_s
        self._resend_after_wall_s = resend_after_wall_s
        self._response_timeout_wall_s = response_timeout_wall_s
        self._late = SecondLook()  # the ROS-time response bound
        self._late_wall = SecondLook()  # the wall-time response bound
        clock = node.get_clock()
        self._now: Callable[[], float] = lambda: clock.now().nanoseconds / 1e9
        self._pending: list[Future] = []  # the request and its resends, oldest first
        self._request: Any = None
        self._started = self._now()
        self._sent = 0.0
        self._sent_wall = 0.0

    def start(self) -> None:
        """Begin a new request period: drop any unanswered request, restart the server bound."""
        self.abandon()
        self._started = self._now()

    def poll(self, make_request: Callable[[], Any]) -> CallResult | None:
        """Advance the request by one tick.

        Args:
            make_request: Builds the request; called once, when the server is ready
                (None: send nothing).

        Returns:
            None while waiting (for the server or its answer), else the :class:`CallResult`.
        """
        now = self._now()
        if not self._pending:
            if not self._client.service_is_ready():
                if now - self._started > self._server_timeout_s:
                    return CallResult(error=f"{self.service_name} service not available "
                                            f"after {self._server_timeout_s:.1f} s")
                return None
            self._request = make_request()
            if self._request is None:  # the caller refused to send: nothing to wait for
                return None
            self._pending.append(self._client.call_async(self._request))
            self._sent = now
            self._sent_wall = time.monotonic()
            self._late.reset()
            self._late_wall.reset()
            return None
        answered = next((f for f in self._pending if f.done()), None)
        if answered is None:
            late = self._late.fails(now - self._sent > self._response_timeout_s)
            # more than one pending: the first resend went out at an earlier poll (see below)
            if late and (self._resend_after_wall_s is None or len(self._pending) > 1):
                self.abandon()
                return CallResult(error=f"no response from {self.service_name} "
                                        f"within {self._response_timeout_s:.1f} s")
            waited_wall = time.monotonic() - self._sent_wall
            wall_bound = self._response_timeout_wall_s
            if self._late_wall.fails(wall_bound is not None and waited_wall > wall_bound):
                self.abandon()
                return CallResult(error=f"no response from {self.service_name} "
                                        f"within {wall_bound:.3g} s (wall)")
            resend = self._resend_after_wall_s
            if resend is not None and waited_wall > resend * len(self._pending):
                self._pending.append(self._client.call_async(self._request))
            return None
        self._pending.remove(answered)
        self.abandon()  # the other copies' answers, if any come, are dropped
        exception = answered.exception()
        if exception is not None:
            return CallResult(error=f"{self.service_name} call failed: {exception}")
        response = answered.result()
        if response is None:
            return CallResult(error=f"{self.service_name} returned no response")
        return CallResult(response=response)

    def waiting_for_server(self) -> bool:
        """Whether the request has not been sent yet because the server is not ready."""
        return not self._pending

    def abandon(self) -> None:
        """Forget the requests still waiting for an answer (late answers are dropped)."""
        for future in self._pending:
            if not future.done():
                self._client.remove_pending_request(future)
                future.cancel()
        self._pending = []

    def destroy(self) -> None:
        """Abandon any request and destroy the client."""
        self.abandon()
        self._node.destroy_client(self._client)
