"""Nav2ActionLeaf: the base of the Nav2 action nodes (Nav2's ``BtActionNode``), asynchronous.

The course's pattern: the ``ActionClient`` is made in ``setup()``; the first tick of an
active period calls :meth:`Nav2ActionLeaf.on_tick` (which fills the goal, or refuses: the
leaf fails) and sends the goal once; later ticks poll the futures and never block;
``terminate()`` cancels a goal still in flight (a halt); the verdict is latched.

Nav2's bounds, without blocking:

* the server must be there within the navigator's ``wait_for_service_timeout`` (1 s) of
  the first tick (Nav2 waits for it when the node is made);
* a sent goal must be acknowledged within ``server_timeout`` (the port, in ms, else the
  navigator's ``default_server_timeout``, 20 ms), measured from the sending on the node's
  clock (ROS time), as Nav2 does, and never shorter in wall time (the answer's round trip
  takes wall time at any simulated speed); Nav2 spins for the answer inside the tick, this
  leaf does not block, so the answer may be waiting in the executor when a tick finds the
  bound passed: that tick lets the executor run once more, the next one fails;
* SUCCEEDED -> :meth:`on_success` (SUCCESS), ABORTED -> :meth:`on_aborted` (FAILURE),
  CANCELED -> :meth:`on_cancelled` (SUCCESS, as in Nav2); a rejected goal fails.

While the goal runs, :meth:`on_wait_for_result` sees each new feedback and may ask for the
goal to be sent again (``self.goal_updated = True``), as FollowPath does for a new path.

A goal with a pose (NavigateToPose's) is told to the mission's events: ``navigation`` when
sent, ``goal_reached`` or ``goal_failed`` (with why) when it ends, each at the goal's pose.
"""

from __future__ import annotations

import importlib
import time
from typing import Any

from py_trees.common import Status

from sar_framework.events.event import EventKind

from .._ros_leaf import RosLeaf
from ._common import node_now, optional_input, server_missing, server_timeout_s


class Nav2ActionLeaf(RosLeaf):
    """A client of one Nav2 action server; subclasses fill the goal and read the result.

    Class attributes:
        ACTION: ``(module, type)`` of the action, e.g. ``("nav2_msgs.action", "Spin")``.
        SERVER: Nav2's default server name.

    Args:
        name: The behaviour's name.
        ports: The leaf's ports (``server_name``, ``server_timeout`` and its own).
    """

    ACTION: tuple[str, str] = ("", "")
    SERVER = ""

    def __init__(self, name: str, *, ports: Any) -> None:
        super().__init__(name)
        self.ports = ports
        self.server_name = self.SERVER
        self.goal: Any = None
        self.goal_updated = False
        self.result: Any = None
        self._action_type: Any = None
        self._client: Any = None
        self._send_future: Any = None
        self._handle: Any = None
        self._result_future: Any = None
        self._feedback: Any = None
        self._started = 0.0
        self._sent = self._sent_wall = 0.0
        self._overdue = False

    # -- hooks ---------------------------------------------------------------------------

    def on_tick(self) -> bool:
        """Fill ``self.goal`` from the ports; return False to fail without sending."""
        return True

    def on_wait_for_result(self, feedback: Any) -> None:
        """See the newest feedback (None when none arrived since the last tick)."""

    def on_success(self) -> Status:
        """The goal succeeded (``self.result`` holds the result): ``error_code_id`` 0."""
        self.set_error_code(0)
        return Status.SUCCESS

    def on_aborted(self) -> Status:
        """The goal was aborted: ``error_code_id`` is the result's code."""
        self.set_error_code(self.result_error_code())
        return Status.FAILURE

    def on_cancelled(self) -> Status:
        """The goal was cancelled by someone else, or this leaf was halted."""
        self.set_error_code(0)
        return Status.SUCCESS

    def set_error_code(self, code: int) -> None:
        """Write ``error_code_id`` when the leaf has that output."""
        if self.ports is not None and "error_code_id" in self.ports.bindings:
            self.ports.set("error_code_id", int(code))

    def result_error_code(self) -> int:
        """The result's ``error_code`` (0, NONE, without one)."""
        return int(getattr(getattr(self.result, "result", None), "error_code", 0))

    # -- py_trees ------------------------------------------------------------------------

    def setup(self, **kwargs: Any) -> None:
        """Take the ROS node and create the action client (``server_name`` or Nav2's name).

        Args:
            **kwargs: Must hold ``node``.
        """
        super().setup(**kwargs)
        from rclpy.action import ActionClient

        module, type_name = self.ACTION
        self._action_type = getattr(importlib.import_module(module), type_name)
        self.server_name = optional_input(self.ports, "server_name", self.SERVER) or self.SERVER
        self._client = ActionClient(self.node, self._action_type, self.server_name)

    def initialise(self) -> None:
        """Start an active period: build the goal (``on_tick``) and send it when possible."""
        self._reset_latch()
        self._send_future = self._handle = self._result_future = self._feedback = None
        self.result = None
        self.goal_updated = False
        self._started = time.monotonic()
        self.goal = self._action_type.Goal()
        if not self.on_tick():
            self._latch(False, self.feedback_message or f"{self.name}: no goal to send")
            return
        if self._client.server_is_ready():
            self._send()
        else:
            self.feedback_message = f"waiting for the {self.server_name} action server"

    def update(self) -> Status:
        """Poll without blocking; RUNNING until the goal ends, then the latched verdict."""
        if self._done:
            return self._verdict()
        now = time.monotonic()
        if self._send_future is None and self._handle is None:
            if self._client.server_is_ready():
                self._send()
                return Status.RUNNING
            missing = server_missing(self._node, self._started, now,
                                     f"\"{self.server_name}\" action server")
            if missing is not None:
                return self._latch(False, missing)
            return Status.RUNNING
        if self._send_future is not None:
            if not self._send_future.done():
                bound = server_timeout_s(self._node, self.ports)
                overdue = (node_now(self._node) - self._sent >= bound
                           and now - self._sent_wall >= bound)
                if not (overdue and self._overdue):
                    self._overdue = overdue
                    return Status.RUNNING
                self._abandon()
                return self._goal_failed("Timed out while waiting for action server to "
                                         f"acknowledge goal request for {self.server_name}")
            future, self._send_future = self._send_future, None
            handle = future.result() if future.exception() is None else None
            if handle is None or not handle.accepted:
                return self._goal_failed(f"goal rejected by {self.server_name}")
            self._handle = handle
            self._result_future = handle.get_result_async()
        feedback, self._feedback = self._feedback, None
        self.on_wait_for_result(feedback)
        if self.goal_updated:
            self.goal_updated = False
            self._send()
            return Status.RUNNING
        if not self._result_future.done():
            return Status.RUNNING
        return self._finish(self._result_future.result())

    def terminate(self, new_status: Status) -> None:
        """On a halt, cancel the goal still in flight (only then) and run ``on_cancelled``."""
        if self._done or (self._send_future is None and self._handle is None):
            return
        self._abandon()
        self.on_cancelled()
        self.feedback_message = f"halted; {self.server_name} goal cancelled"
        self.node.get_logger().info(f"{self.name}: {self.feedback_message}")

    def shutdown(self) -> None:
        """Destroy the action client."""
        if self._client is not None:
            self._client.destroy()
            self._client = None

    # -- helpers -------------------------------------------------------------------------

    def _send(self) -> None:
        self._handle = self._result_future = None
        self._send_future = self._client.send_goal_async(self.goal,
                                                         feedback_callback=self._on_feedback)
        self._sent, self._sent_wall = node_now(self._node), time.monotonic()
        self._overdue = False
        self.feedback_message = f"goal sent to {self.server_name}"
        self._goal_event(EventKind.NAVIGATION, f"sent to {self.server_name}")

    def _on_feedback(self, message: Any) -> None:
        self._feedback = message.feedback

    def _finish(self, wrapped: Any) -> Status:
        from action_msgs.msg import GoalStatus

        self.result = wrapped
        self._handle = self._result_future = None
        status = getattr(wrapped, "status", GoalStatus.STATUS_UNKNOWN)
        code = self.result_error_code()
        if status == GoalStatus.STATUS_SUCCEEDED:
            verdict, text = self.on_success(), "succeeded"
        elif status == GoalStatus.STATUS_ABORTED:
            verdict, text = self.on_aborted(), f"aborted (error code {code})"
        elif status == GoalStatus.STATUS_CANCELED:
            verdict, text = self.on_cancelled(), "cancelled"
        else:
            verdict, text = Status.FAILURE, f"ended with status {status}"
        message = getattr(getattr(wrapped, "result", None), "error_msg", "")
        detail = f": {message}" if message else ""
        reached = status == GoalStatus.STATUS_SUCCEEDED
        if reached:
            self._goal_event(EventKind.GOAL_REACHED, "reached", "SUCCEEDED")
        else:
            self._goal_event(EventKind.GOAL_FAILED,
                             f"not reached: {self.server_name} {text}{detail}", "FAILED")
        # a success is not logged, as Nav2's BtActionNode says nothing then (rclpy's logger
        # finds its caller's source file on every call: milliseconds inside the 10 ms tick)
        return self._latch(verdict == Status.SUCCESS, f"{self.server_name} {text}{detail}",
                           log=verdict != Status.SUCCESS)

    def _goal_failed(self, reason: str) -> Status:
        """Fail with ``reason``, told as the goal's ``goal_failed`` event too."""
        self._goal_event(EventKind.GOAL_FAILED, f"not reached: {reason}", "FAILED")
        return self._latch(False, reason)

    def _goal_event(self, kind: EventKind, what: str, status: str = "") -> None:
        """Emit ``kind`` at the goal's pose, if the goal has one: "goal (x, y) <what>"."""
        position = getattr(getattr(getattr(self.goal, "pose", None), "pose", None),
                           "position", None)
        if position is None:
            return
        self.events.emit(kind, source=self, status=status,
                         message=f"goal ({position.x:.2f}, {position.y:.2f}) {what}",
                         position=(position.x, position.y))

    def _abandon(self) -> None:
        """Cancel the goal in flight, now or once it is accepted; forget the futures."""
        if self._handle is not None:
            self._handle.cancel_goal_async()
        elif self._send_future is not None:
            self._send_future.add_done_callback(_cancel_if_accepted)
        self._send_future = self._handle = self._result_future = None


def _cancel_if_accepted(future: Any) -> None:
    """Cancel a goal whose acceptance arrives after the leaf stopped wanting it."""
    if future.exception() is None and future.result() is not None and future.result().accepted:
        future.result().cancel_goal_async()
