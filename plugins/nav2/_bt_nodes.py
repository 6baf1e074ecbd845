"""Nav2's ``BtActionNode`` and ``BtServiceNode`` on the leaf toolkit: Nav2's hooks and bounds.

The goal or request life cycle is the toolkit's (:class:`~sar_framework.leaves.ActionLeaf`,
:class:`~sar_framework.leaves.ServiceLeaf`); this module only gives Nav2's leaves Nav2's
moments and settings:

* the server is the ``server_name`` / ``service_name`` port, else Nav2's default name;
* :meth:`Nav2ActionLeaf.on_tick` fills ``self.goal`` (False: FAILURE without sending);
  :meth:`Nav2ActionLeaf.on_wait_for_result` sees each tick's feedback and may set
  ``goal_updated`` to send the goal again (FollowPath's new path);
* SUCCEEDED -> :meth:`on_success` (SUCCESS), ABORTED -> :meth:`on_aborted` (FAILURE),
  CANCELED -> :meth:`on_cancelled` (SUCCESS, as in Nav2), each writing ``error_code_id``;
* the server must be ready within the navigator's ``wait_for_service_timeout`` (on the
  node's clock); the goal's acknowledgement is bounded by ``server_timeout`` (the port, ms,
  else the navigator's ``default_server_timeout``; wall time, as Nav2's executor spins for
  it), judged as :class:`~sar_framework.leaves.PolledGoal` does: never on the time between
  two ticks alone. A service's answer gets ``server_timeout`` the same way.

A goal with a pose (NavigateToPose's) is told to the mission's events: ``navigation`` when
sent, ``goal_reached`` or ``goal_failed`` (with why) when it ends, each at the goal's pose.
"""

from __future__ import annotations

import math
from typing import Any

from py_trees.common import Status

from sar_framework.events.event import EventKind
from sar_framework.leaves import (
    STATUS_ABORTED,
    STATUS_CANCELED,
    STATUS_SUCCEEDED,
    ActionLeaf,
    GoalFailure,
    RosLeaf,
    ServiceLeaf,
)

from ._common import optional_input, server_timeout_s, wait_for_service_s


class Nav2ActionLeaf(ActionLeaf):
    """A client of one Nav2 action server; subclasses fill the goal and read the result.

    Class attributes:
        action_type: The action, e.g. ``nav2_msgs/action/Spin``.
        SERVER: Nav2's default server name.

    Args:
        name: The behaviour's name.
        ports: The leaf's ports (``server_name``, ``server_timeout`` and its own).
    """

    SERVER = ""
    #: A planner's output port for the result's path, emptied when it fails ("": none).
    PATH_OUTPUT = ""

    def __init__(self, name: str, *, ports: Any) -> None:
        super().__init__(name, ports=ports)
        self.goal_updated = False

    def on_tick(self) -> bool:
        """Fill ``self.goal`` from the ports; return False to fail without sending."""
        return True

    def on_wait_for_result(self, feedback: Any) -> None:
        """See the newest feedback (None when none arrived since the last tick)."""

    def on_success(self) -> Status:
        """The goal succeeded (``self.result`` holds the result): ``error_code_id`` 0."""
        self.set_path(self.result.path if self.PATH_OUTPUT else None)
        self.set_error_code(0)
        return Status.SUCCESS

    def on_aborted(self) -> Status:
        """The goal was aborted: ``error_code_id`` is the result's code."""
        self.set_path(None)
        self.set_error_code(self.result_error_code())
        return Status.FAILURE

    def on_cancelled(self) -> Status:
        """The goal was cancelled by someone else, or this leaf was halted."""
        self.set_path(None)
        self.set_error_code(0)
        return Status.SUCCESS

    def set_path(self, path: Any) -> None:
        """Write ``path`` (None: an empty path) to :attr:`PATH_OUTPUT`, if the leaf has one."""
        if not self.PATH_OUTPUT:
            return
        if path is None:
            from nav_msgs.msg import Path

            path = Path()
        self.ports.set(self.PATH_OUTPUT, path)

    def set_error_code(self, code: int) -> None:
        """Write ``error_code_id`` when the leaf has that output."""
        if self.ports is not None and "error_code_id" in self.ports.bindings:
            self.ports.set("error_code_id", int(code))

    def result_error_code(self) -> int:
        """The result's ``error_code`` (0, NONE, without one)."""
        return int(getattr(self.result, "error_code", 0))

    # -- the toolkit's hooks, in Nav2's terms ------------------------------------------------

    def setup(self, **kwargs: Any) -> None:
        """Name the server and set Nav2's bounds, then create the client.

        Args:
            **kwargs: Must hold ``node``.
        """
        node = kwargs.get("node")
        self.action_name = optional_input(self.ports, "server_name", self.SERVER) or self.SERVER
        self.server_timeout_s = wait_for_service_s(node)
        self.ack_timeout_wall_s = server_timeout_s(node, self.ports)
        super().setup(**kwargs)

    def initialise(self) -> None:
        """Start a goal period."""
        self.goal_updated = False
        super().initialise()

    def set_goal(self, goal: Any) -> bool:
        """Let :meth:`on_tick` fill the goal."""
        self.goal = goal
        return self.on_tick()

    def on_sent(self) -> None:
        """Tell the goal's ``navigation`` event."""
        self._goal_event(EventKind.NAVIGATION, f"sent to {self.action_name}")

    def on_feedback(self, feedback: Any) -> None:
        """Nav2's ``on_wait_for_result``; send the goal again when it was updated."""
        self.on_wait_for_result(feedback)
        if self.goal_updated:
            self.goal_updated = False
            self.resend()

    def on_result(self, status: int, result: Any) -> Status:
        """Nav2's verdict on the result code, told as the goal's event."""
        code = self.result_error_code()
        if status == STATUS_SUCCEEDED:
            verdict, text = self.on_success(), "succeeded"
        elif status == STATUS_ABORTED:
            verdict, text = self.on_aborted(), f"aborted (error code {code})"
        elif status == STATUS_CANCELED:
            verdict, text = self.on_cancelled(), "cancelled"
        else:
            verdict, text = Status.FAILURE, f"ended with status {status}"
        message = getattr(result, "error_msg", "")
        said = f"{self.action_name} {text}" + (f": {message}" if message else "")
        if status == STATUS_SUCCEEDED:
            self._goal_event(EventKind.GOAL_REACHED, "reached", "SUCCEEDED")
        else:
            self._goal_event(EventKind.GOAL_FAILED, f"not reached: {said}", "FAILED")
        # a success is not logged, as Nav2's BtActionNode says nothing then
        return self.latch(verdict == Status.SUCCESS, said, log=verdict != Status.SUCCESS)

    def on_failure(self, failure: GoalFailure, reason: str) -> Status:
        """Fail in Nav2's words, told as the goal's ``goal_failed`` event."""
        if failure == GoalFailure.SERVER_UNREACHABLE:
            reason = (f"\"{self.action_name}\" action server not available after waiting "
                      f"for {self.server_timeout_s:g} s")
        elif failure == GoalFailure.SEND_GOAL_TIMEOUT:
            reason = ("Timed out while waiting for action server to acknowledge goal request "
                      f"for {self.action_name}")
        self._goal_event(EventKind.GOAL_FAILED, f"not reached: {reason}", "FAILED")
        return self.fail(reason)

    def on_halted(self) -> None:
        """Nav2's ``on_cancelled`` on a halt, and a log line."""
        self.on_cancelled()
        self.node.get_logger().info(f"{self.name}: {self.feedback_message}")

    def _goal_event(self, kind: EventKind, what: str, status: str = "") -> None:
        """Emit ``kind`` at the goal's pose, if the goal has one: "goal (x, y) <what>"."""
        position = getattr(getattr(getattr(self.goal, "pose", None), "pose", None),
                           "position", None)
        if position is None:
            return
        self.events.emit(kind, source=self, status=status,
                         message=f"goal ({position.x:.2f}, {position.y:.2f}) {what}",
                         position=(position.x, position.y))


class Nav2ServiceLeaf(ServiceLeaf):
    """A client of one Nav2 service; subclasses fill the request and read the response.

    Class attributes:
        service_type: The service, e.g. ``nav2_msgs/srv/ClearEntireCostmap``.
        SERVER: The service name used without a ``service_name`` port ("": none).

    Args:
        name: The behaviour's name.
        ports: The leaf's ports (``service_name``, ``server_timeout`` and its own).
    """

    SERVER = ""

    def __init__(self, name: str, *, ports: Any) -> None:
        super().__init__(name, ports=ports)
        self.response: Any = None

    def on_tick(self) -> bool:
        """Fill ``self.request`` from the ports; return False to fail without calling."""
        return True

    def on_completion(self) -> Status:
        """The response arrived (``self.response``)."""
        return Status.SUCCESS

    def service_from_ports(self) -> str:
        """The service to call: the ``service_name`` port, else :attr:`SERVER` ("": none)."""
        return optional_input(self.ports, "service_name", self.SERVER) or ""

    def setup(self, **kwargs: Any) -> None:
        """Name the service and set Nav2's bounds, then create the client.

        Args:
            **kwargs: Must hold ``node``.
        """
        node = kwargs.get("node")
        self.service_name = self.service_from_ports()
        self.server_timeout_s = wait_for_service_s(node)
        self.response_timeout_s = math.inf  # the wall bound alone, as Nav2's
        self.response_timeout_wall_s = server_timeout_s(node, self.ports)
        if self.service_name:
            super().setup(**kwargs)
        else:  # the node alone: there is nothing to call
            RosLeaf.setup(self, **kwargs)

    def initialise(self) -> None:
        """Start a request period (FAILURE at once without a service name)."""
        self.response = None
        if not self.service_name:
            self.reset_latch()
            self.fail(f"{self.name}: no service_name given")
            return
        super().initialise()

    def set_request(self, request: Any) -> bool:
        """Let :meth:`on_tick` fill the request."""
        self.request = request
        return self.on_tick()

    def on_response(self, response: Any) -> Status:
        """Nav2's verdict on the response (a success is not logged, as in Nav2)."""
        self.response = response
        verdict = self.on_completion()
        return self.latch(verdict == Status.SUCCESS, f"{self.service_name} answered",
                          log=verdict != Status.SUCCESS)

    def on_failure(self, reason: str) -> Status:
        """Fail in Nav2's words when the answer is late."""
        if reason.startswith("no response from"):
            reason = f"Node timed out while executing service call to {self.service_name}."
        return self.fail(reason)
