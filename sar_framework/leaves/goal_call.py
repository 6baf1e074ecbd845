"""PolledGoal: one bounded, non-blocking ROS action goal, polled by tick.

The goal's life cycle for a leaf that must never block: wait for the action server, send
the goal, wait for its acceptance, then for its result; cancel it on request, even before
its acceptance has arrived (the cancel is sent as soon as the acceptance does). The bounds
count on the node's clock (ROS time: simulated seconds with ``use_sim_time``):

* ``server_timeout_s`` from :meth:`PolledGoal.start` until the server is ready;
* ``result_timeout_s`` (None: none) from the goal's sending until its result, acceptance
  included;
* ``ack_timeout_wall_s`` (None: none) from the sending until the acceptance, in wall
  seconds: the acceptance is a transport round trip, not simulated work (Nav2's
  ``server_timeout``, which Nav2 spends spinning its executor inside one tick). With
  ``ack_resends`` (0: none), a goal not accepted in time is sent again (a new goal of the
  same content, which preempts the first should it have arrived after all; the first is
  cancelled if its acceptance comes late) before the goal fails. A lost request or answer
  then costs one bound, not the mission.

A bound is judged only for the stage the goal is in: a goal is sent only once its server is
ready, so the wait for the server never eats into the acceptance. And a tick never fails a
goal on the acceptance bound alone: the bound must already have passed at an earlier tick,
so the executor has had its turn between the two ticks to deliver an acceptance that was on
its way. The time between two ticks of a loaded machine is then not all a goal gets.
"""

from __future__ import annotations

import enum
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from sar_framework.leaves.second_look import SecondLook

if TYPE_CHECKING:
    from rclpy.node import Node

#: ``action_msgs/msg/GoalStatus`` codes, named (the values are ROS's).
STATUS_SUCCEEDED = 4
STATUS_CANCELED = 5
STATUS_ABORTED = 6


class GoalFailure(enum.Enum):
    """Why a goal ended without a result (BehaviorTree.ROS2's ``ActionNodeErrorCode``)."""

    SERVER_UNREACHABLE = "server unreachable"
    SEND_GOAL_TIMEOUT = "goal not accepted in time"
    GOAL_REJECTED = "goal rejected"
    RESULT_TIMEOUT = "result not in time"
    INVALID_GOAL = "invalid goal"


@dataclass(frozen=True)
class GoalEnd:
    """How one goal ended: a status and result, or a failure and its reason.

    Attributes:
        status: The goal's final ``GoalStatus`` code (0, UNKNOWN, on a failure).
        result: The action's result message (None on a failure).
        failure: Why there is no result (None when there is one).
        reason: The failure in words, naming the action.
    """

    status: int = 0
    result: Any = None
    failure: GoalFailure | None = None
    reason: str = ""


class PolledGoal:
    """An action client that runs one goal per :meth:`start` and never blocks.

    Args:
        node: The node that owns the client.
        action_type: The action type (e.g. ``nav2_msgs.action.Spin``).
        action_name: The action server's name (relative: in the node's namespace).
        server_timeout_s: Seconds the server may take to become ready.
        result_timeout_s: Seconds from the sending to the result (None: unbounded).
        ack_timeout_wall_s: Wall seconds from the sending to the acceptance (None: only the
            result bound).
        ack_resends: How many times a goal not accepted within ``ack_timeout_wall_s`` is
            sent again before it fails.
    """

    def __init__(self, node: Node, action_type: Any, action_name: str, *,
                 server_timeout_s: float, result_timeout_s: float | None = None,
                 ack_timeout_wall_s: float | None = None, ack_resends: int = 0) -> None:
        from rclpy.action import ActionClient

        self._node = node
        self._client = ActionClient(node, action_type, action_name)
        self.action_name = action_name
        self.server_timeout_s = server_timeout_s
        self.result_timeout_s = result_timeout_s
        self.ack_timeout_wall_s = ack_timeout_wall_s
        self.ack_resends = ack_resends
        self._ack_late = SecondLook()  # the acceptance bound
        self._resends_left = ack_resends
        self._goal: Any = None
        self._send_future: Any = None
        self._handle: Any = None
        self._result_future: Any = None
        self._feedback: Any = None
        self._started = self._now()
        self._sent = 0.0
        self._sent_wall = 0.0

    def _now(self) -> float:
        return self._node.get_clock().now().nanoseconds / 1e9

    @property
    def in_flight(self) -> bool:
        """Whether a goal was sent and has not ended (accepted or not yet answered)."""
        return self._send_future is not None or self._handle is not None

    @property
    def accepted(self) -> bool:
        """Whether the goal in flight has been accepted."""
        return self._handle is not None

    def start(self) -> None:
        """Begin a new goal period: cancel any goal in flight, restart the server bound."""
        self.cancel()
        self._feedback = None
        self._started = self._now()
        self._resends_left = self.ack_resends

    def send(self, goal: Any) -> None:
        """Send ``goal`` now (the server must be ready); a goal in flight is replaced.

        The server sees a new goal: as with Nav2's updated goals, it preempts the old one.
        """
        self._handle = self._result_future = None
        self._goal = goal
        self._send_future = self._client.send_goal_async(goal,
                                                         feedback_callback=self._on_feedback)
        self._sent = self._now()
        self._sent_wall = time.monotonic()
        self._ack_late.reset()

    def take_feedback(self) -> Any:
        """The newest feedback message since the last call, or None."""
        feedback, self._feedback = self._feedback, None
        return feedback

    def poll(self, make_goal: Callable[[], Any]) -> GoalEnd | None:
        """Advance the goal by one tick.

        Args:
            make_goal: Builds the goal; called once, when the server is ready (None: send
                nothing and wait no more).

        Returns:
            None while waiting (for the server, the acceptance or the result), else the
            :class:`GoalEnd`.
        """
        now = self._now()
        if not self.in_flight:
            if not self._client.server_is_ready():
                if now - self._started > self.server_timeout_s:
                    return GoalEnd(failure=GoalFailure.SERVER_UNREACHABLE,
                                   reason=f"{self.action_name} server not available after "
                                          f"{self.server_timeout_s:.1f} s")
                return None
            goal = make_goal()
            if goal is not None:
                self.send(goal)
            return None
        if self._handle is None:
            if not self._send_future.done():
                return self._late(now)
            future, self._send_future = self._send_future, None
            handle = future.result() if future.exception() is None else None
            if handle is None or not handle.accepted:
                why = f": {future.exception()}" if future.exception() is not None else ""
                return GoalEnd(failure=GoalFailure.GOAL_REJECTED,
                               reason=f"goal rejected by {self.action_name}{why}")
            self._handle = handle
            self._result_future = handle.get_result_async()
        if not self._result_future.done():
            return self._late(now)
        wrapped = self._result_future.result()
        self._handle = self._result_future = None
        return GoalEnd(status=int(getattr(wrapped, "status", 0)),
                       result=getattr(wrapped, "result", None))

    def _late(self, now: float) -> GoalEnd | None:
        """The failure of a goal past its acknowledgement or result bound, else None."""
        waited = now - self._sent
        bound = self.ack_timeout_wall_s
        late = bound is not None and time.monotonic() - self._sent_wall > bound
        if self._ack_late.fails(self._handle is None and late):
            self.cancel()
            if self._resends_left > 0:
                self._resends_left -= 1
                self._node.get_logger().warning(
                    f"{self.action_name} did not accept the goal within {bound:.3g} s; "
                    "sending it again")
                self.send(self._goal)
                return None
            sent = f" (sent {self.ack_resends + 1} times)" if self.ack_resends else ""
            return GoalEnd(failure=GoalFailure.SEND_GOAL_TIMEOUT,
                           reason=f"{self.action_name} did not accept the goal within "
                                  f"{bound:.3g} s{sent}")
        if self.result_timeout_s is not None and waited > self.result_timeout_s:
            answered = self._handle is not None
            self.cancel()
            if not answered:
                return GoalEnd(failure=GoalFailure.SEND_GOAL_TIMEOUT,
                               reason=f"{self.action_name} did not answer the goal within "
                                      f"{self.result_timeout_s:.1f} s")
            return GoalEnd(failure=GoalFailure.RESULT_TIMEOUT,
                           reason=f"{self.action_name} goal not finished within "
                                  f"{self.result_timeout_s:.1f} s; goal cancelled")
        return None

    def cancel(self) -> None:
        """Cancel the goal in flight, now or as soon as its acceptance arrives."""
        if self._handle is not None:
            self._handle.cancel_goal_async()
        elif self._send_future is not None:
            self._send_future.add_done_callback(_cancel_if_accepted)
        self._send_future = self._handle = self._result_future = None

    def destroy(self) -> None:
        """Cancel any goal in flight and destroy the client."""
        self.cancel()
        self._client.destroy()

    def _on_feedback(self, message: Any) -> None:
        self._feedback = message.feedback


def _cancel_if_accepted(future: Any) -> None:
    """Cancel a goal whose acceptance arrives after its sender stopped wanting it."""
    if future.exception() is None and future.result() is not None and future.result().accepted:
        future.result().cancel_goal_async()


class GoalBatch:
    """Several goals to one action server at once, each polled to its end, never blocking.

    For a leaf that asks many questions of one server in one tick (a path cost per waypoint).
    No feedback, no bounds of its own: the caller decides how long it waits (:meth:`drop`).

    Args:
        node: The node that owns the client.
        action_type: The action type.
        action_name: The action server's name (relative: in the node's namespace).
    """

    def __init__(self, node: Node, action_type: Any, action_name: str) -> None:
        from rclpy.action import ActionClient

        self.action_type = action_type
        self.action_name = action_name
        self._client = ActionClient(node, action_type, action_name)
        self._sent: dict[str, Any] = {}
        self._results: dict[str, Any] = {}

    def server_is_ready(self) -> bool:
        """Whether the action server is there."""
        return bool(self._client.server_is_ready())

    def send(self, key: str, goal: Any) -> None:
        """Send ``goal``, known as ``key`` (the server must be ready)."""
        self._sent[key] = self._client.send_goal_async(goal)

    @property
    def pending(self) -> bool:
        """Whether some goal has not ended yet."""
        return bool(self._sent or self._results)

    def poll(self) -> dict[str, GoalEnd]:
        """The goals that ended since the last poll, by key (a rejected one as a failure)."""
        ended: dict[str, GoalEnd] = {}
        for key, future in list(self._sent.items()):
            if not future.done():
                continue
            del self._sent[key]
            handle = future.result() if future.exception() is None else None
            if handle is not None and handle.accepted:
                self._results[key] = handle.get_result_async()
            else:
                ended[key] = GoalEnd(failure=GoalFailure.GOAL_REJECTED,
                                     reason=f"goal rejected by {self.action_name}")
        for key, future in list(self._results.items()):
            if not future.done():
                continue
            del self._results[key]
            wrapped = future.result() if future.exception() is None else None
            ended[key] = GoalEnd(status=int(getattr(wrapped, "status", 0)),
                                 result=getattr(wrapped, "result", None))
        return ended

    def drop(self) -> None:
        """Forget the goals that have not ended (their answers, if any come, are ignored)."""
        self._sent, self._results = {}, {}

    def destroy(self) -> None:
        """Destroy the client."""
        self._client.destroy()
