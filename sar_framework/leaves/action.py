"""ActionLeaf: a client of one ROS 2 action, one goal per activation, never blocking.

On the semantics of BehaviorTree.ROS2's ``RosActionNode`` and Nav2's ``BtActionNode``:

* the goal is built in one method, :meth:`ActionLeaf.set_goal`, from the leaf's params and
  ports, on the first tick the server is ready (False refuses: the leaf fails);
* :meth:`ActionLeaf.on_feedback` sees the newest feedback on every tick the goal runs and
  may end the leaf early (the goal is then cancelled);
* :meth:`ActionLeaf.on_result` turns the goal's final status (SUCCEEDED, ABORTED,
  CANCELED) and result into the leaf's status; :meth:`ActionLeaf.on_failure` does the same
  for a goal that got no result (:class:`~.goal_call.GoalFailure`);
* a halt cancels the goal in flight, even before its acceptance has arrived;
* the bounds (``server_timeout_s`` until the server is ready, ``result_timeout_s`` from the
  sending to the result) count on the node's clock (:class:`~.goal_call.PolledGoal`); a
  subclass may also bound the acceptance (``ack_timeout_wall_s``, wall seconds) and send a
  goal not accepted in time again (``ack_resends``) before it fails;
* the reason of every ending is in ``feedback_message``.

Imports no ROS package at import.
"""

from __future__ import annotations

from typing import Any, ClassVar

from py_trees.common import Status

from sar_framework.engine.param import Param
from sar_framework.leaves.declared import interface_type
from sar_framework.leaves.goal_call import (
    STATUS_ABORTED,
    STATUS_CANCELED,
    STATUS_SUCCEEDED,
    GoalFailure,
    PolledGoal,
)
from sar_framework.leaves.ros_leaf import RosLeaf

_STATUS_WORDS = {STATUS_SUCCEEDED: "succeeded", STATUS_ABORTED: "aborted",
                 STATUS_CANCELED: "cancelled"}


def action_params(action_name: str, *, server_timeout_s: float = 10.0,
                  result_timeout_s: float = 300.0) -> tuple[Param, ...]:
    """The params an :class:`ActionLeaf` reads: the server's name and the two bounds.

    Args:
        action_name: The default action server name (relative names resolve in the node's
            namespace).
        server_timeout_s: The default bound on waiting for the server (ROS seconds).
        result_timeout_s: The default bound from sending the goal to its result.

    Returns:
        ``action_name``, ``server_timeout_s`` and ``result_timeout_s``.
    """
    return (
        Param("action_name", str, default=action_name, description="The action server."),
        Param("server_timeout_s", float, default=server_timeout_s, exclusive_minimum=0.0,
              description="Fail if the action server is not ready within this many seconds "
                          "(ROS time)."),
        Param("result_timeout_s", float, default=result_timeout_s, exclusive_minimum=0.0,
              description="Cancel the goal and fail if it has no result this many seconds "
                          "after it was sent (ROS time)."),
    )


class ActionLeaf(RosLeaf):
    """A client of one ROS 2 action: one goal per activation, polled by tick.

    Set :attr:`action_type`; declare :func:`action_params` (or set ``action_name``,
    ``server_timeout_s`` and ``result_timeout_s`` otherwise); override :meth:`set_goal`,
    and :meth:`on_result` or :meth:`on_feedback` when the defaults do not fit.

    Example::

        @leaf(params=[Param("order", int, default=5), *action_params("fibonacci")])
        class Fibonacci(ActionLeaf):
            action_type = "example_interfaces/action/Fibonacci"

            def set_goal(self, goal):
                goal.order = self.order

    Args:
        name: The behaviour's name.
        **declared: The declared params (``action_name``, ``server_timeout_s``,
            ``result_timeout_s`` and the leaf's own), context objects and ``ports``.
    """

    #: The action type as ``ros2 interface`` names it (``nav2_msgs/action/Spin``).
    action_type: ClassVar[str] = ""

    def __init__(self, name: str, **declared: Any) -> None:
        self.action_name: str = ""
        self.server_timeout_s: float = 10.0
        self.result_timeout_s: float | None = None
        self.ack_timeout_wall_s: float | None = None
        self.ack_resends: int = 0
        super().__init__(name, **declared)
        self.goal: Any = None
        self.result: Any = None
        self._goal_call: PolledGoal | None = None
        self._type: Any = None

    # -- what a subclass says -------------------------------------------------------------

    def set_goal(self, goal: Any) -> bool | None:
        """Fill ``goal`` (a fresh ``Goal``) once the server is ready.

        Args:
            goal: The goal to fill.

        Returns:
            False to fail without sending (say why in ``feedback_message``); None or True
            to send it.
        """
        return None

    def on_sent(self) -> None:
        """Called once the goal (``goal``) has been sent."""

    def on_feedback(self, feedback: Any) -> Status | None:
        """See the goal's progress on every tick it runs.

        Args:
            feedback: The newest feedback since the last tick, or None.

        Returns:
            None (or RUNNING) to keep going; SUCCESS or FAILURE to end the leaf now (the
            goal is cancelled; set ``feedback_message`` first to say why).
        """
        return None

    def on_result(self, status: int, result: Any) -> Status:
        """Judge the goal's end: SUCCESS when it succeeded, FAILURE otherwise.

        Args:
            status: The final ``GoalStatus`` code (``STATUS_SUCCEEDED``, ``_ABORTED``,
                ``_CANCELED``).
            result: The action's result message.

        Returns:
            The leaf's verdict, usually through :meth:`~sar_framework.leaves.RosLeaf.succeed` or
            :meth:`~sar_framework.leaves.RosLeaf.fail`.
        """
        said = f"{self.action_name} {_STATUS_WORDS.get(status, f'ended with status {status}')}"
        detail = getattr(result, "error_msg", "")
        said += f": {detail}" if detail else ""
        return self.succeed(said) if status == STATUS_SUCCEEDED else self.fail(said)

    def on_failure(self, failure: GoalFailure, reason: str) -> Status:
        """Judge a goal that got no result (no server, rejected, a bound passed).

        Args:
            failure: Which way it failed.
            reason: The same in words, naming the action server.

        Returns:
            The leaf's verdict; FAILURE by default.
        """
        return self.fail(reason)

    def on_halted(self) -> None:
        """Called after a halt cancelled the goal in flight."""

    def resend(self) -> None:
        """Send ``goal`` again, as updated (from :meth:`on_feedback`); the server preempts."""
        self._goals().send(self.goal)
        self.on_sent()

    # -- the life cycle -------------------------------------------------------------------

    def setup(self, **kwargs: Any) -> None:
        """Take the ROS node and create the action client.

        Args:
            **kwargs: Must hold ``node``; may hold ``events``.
        """
        super().setup(**kwargs)
        self._type = interface_type(self.action_type)
        self._goal_call = PolledGoal(self.node, self._type, self.action_name,
                                     server_timeout_s=self.server_timeout_s,
                                     result_timeout_s=self.result_timeout_s,
                                     ack_timeout_wall_s=self.ack_timeout_wall_s,
                                     ack_resends=self.ack_resends)

    def initialise(self) -> None:
        """Forget the last verdict and goal; start a new goal period."""
        self.reset_latch()
        self.goal = self.result = None
        self._goals().start()

    def update(self) -> Status:
        """Poll the goal without blocking.

        Returns:
            RUNNING until the goal ends, then the latched verdict.
        """
        if self._done:
            return self.verdict()
        goals = self._goals()
        was_sent = goals.in_flight
        end = goals.poll(self._make_goal)
        if self._done:  # set_goal refused
            return self.verdict()
        if not was_sent and goals.in_flight:
            self.feedback_message = f"goal sent to {self.action_name}"
            self.on_sent()
        if end is None:
            if not goals.in_flight:
                self.feedback_message = f"waiting for the {self.action_name} action server"
                return Status.RUNNING
            early = self.on_feedback(goals.take_feedback())
            if early in (Status.SUCCESS, Status.FAILURE):
                goals.cancel()
                return self.latch(early == Status.SUCCESS,
                                  self.feedback_message or f"{self.name} ended the goal")
            return Status.RUNNING
        if end.failure is not None:
            return self.on_failure(end.failure, end.reason)
        self.result = end.result
        return self.on_result(end.status, end.result)

    def terminate(self, new_status: Status) -> None:
        """On a halt, cancel the goal still in flight (only then) and call :meth:`on_halted`.

        Args:
            new_status: The status the leaf is moving to.
        """
        if self._done or self._goal_call is None or not self._goal_call.in_flight:
            return
        self._goal_call.cancel()
        self.feedback_message = f"halted; {self.action_name} goal cancelled"
        self.on_halted()

    def shutdown(self) -> None:
        """Destroy the action client."""
        if self._goal_call is not None:
            self._goal_call.destroy()
            self._goal_call = None

    def _make_goal(self) -> Any:
        goal = self._type.Goal()
        if self.set_goal(goal) is False:
            self.fail(self.feedback_message or f"{self.name}: no goal to send")
            return None
        self.goal = goal
        return goal

    def _goals(self) -> PolledGoal:
        if self._goal_call is None:
            raise RuntimeError(f"{type(self).__name__} '{self.name}' used before setup(node=...)")
        return self._goal_call
