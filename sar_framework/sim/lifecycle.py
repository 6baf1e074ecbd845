"""Nav2's lifecycle for the simulated servers: rclpy lifecycle nodes, managed as Nav2 does.

Each simulated Nav2 server is a :class:`Nav2LifecycleNode`: rclpy's ``LifecycleNode``
(``~/change_state``, ``~/get_state``, ``~/get_available_transitions``, ...,
``~/transition_event``), so ``ros2 lifecycle list/set/get`` work on it. Its action servers
refuse goals unless the node is ACTIVE, as ``nav2_util::SimpleActionServer`` does ("Action
server is inactive. Rejecting the goal.").

Types that only the full ``nav2_msgs`` provides are looked up with :func:`optional_type`: on
the fallback tier (the stand-in ``nav2_msgs``, ``NavigateToPose`` only) the servers needing
them are not offered, and the simulator says which in one log line.

A fleet's robots are built inside :func:`robot_namespace`: every node made there lives in
that robot's namespace (``/robot1/planner_server``, ``/robot1/global_costmap/global_costmap``),
as nav2_bringup's ``use_namespace`` puts one Nav2 stack per robot.
"""

from __future__ import annotations

import importlib
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Any

from rclpy.action import ActionServer, CancelResponse, GoalResponse
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.lifecycle import LifecycleNode, LifecycleState, TransitionCallbackReturn

_not_offered: list[str] = []
_robot_ns: ContextVar[str] = ContextVar("robot_namespace", default="")


@contextmanager
def robot_namespace(name: str) -> Iterator[None]:
    """Make the nodes created inside live under ``/name`` ('' = the root, one robot)."""
    token = _robot_ns.set(name.strip("/"))
    try:
        yield
    finally:
        _robot_ns.reset(token)


def in_robot_namespace(namespace: str = "") -> str:
    """``namespace`` (relative, may be '') inside the current robot's namespace.

    Returns:
        The node namespace to give rclpy: ``/robot1/global_costmap``, or ``global_costmap``
        and '' outside a fleet (rclpy's defaults, unchanged).
    """
    robot = _robot_ns.get()
    if not robot:
        return namespace
    return "/" + "/".join(part for part in (robot, namespace.strip("/")) if part)


def optional_type(module: str, name: str, *, needed_by: str) -> Any | None:
    """Import an interface type, or note that ``needed_by`` is not offered and return None.

    Args:
        module: E.g. ``"nav2_msgs.action"``.
        name: E.g. ``"Spin"``.
        needed_by: What is not offered without it (see :func:`take_not_offered`).
    """
    try:
        return getattr(importlib.import_module(module), name)
    except (ImportError, AttributeError):
        _not_offered.append(f"{needed_by} ({module.split('.', maxsplit=1)[0]}/{name})")
        return None


def take_not_offered() -> list[str]:
    """Return (and forget) what :func:`optional_type` could not offer so far."""
    taken = list(_not_offered)
    _not_offered.clear()
    return taken


class Nav2LifecycleNode(LifecycleNode):
    """A simulated Nav2 server: a lifecycle node whose action servers need it ACTIVE.

    Args:
        name: Node name (``planner_server``, ...).
        namespace: Node namespace (the costmaps live in ``/global_costmap`` etc.).
    """

    def __init__(self, name: str, namespace: str | None = None) -> None:
        super().__init__(name, namespace=in_robot_namespace(namespace or ""))
        self._active = threading.Event()
        self.group = ReentrantCallbackGroup()
        self.on_active_change: list[Callable[[bool], None]] = []
        self.children: list[Nav2LifecycleNode] = []  # e.g. planner_server's global_costmap

    @property
    def active(self) -> bool:
        """Whether the node is in the ACTIVE state."""
        return self._active.is_set()

    def state_id(self) -> int:
        """The current primary state's id (``lifecycle_msgs/msg/State``)."""
        return self._state_machine.current_state[0]

    def _set_active(self, active: bool) -> None:
        if active:
            self._active.set()
        else:
            self._active.clear()
        for callback in self.on_active_change:
            callback(active)

    def _children(self, transition: str) -> None:
        """Take the same transition on each child node (Nav2's servers own their costmaps)."""
        for child in self.children:
            getattr(child, f"trigger_{transition}")()

    def on_configure(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Configure the children."""
        self._children("configure")
        return super().on_configure(state)

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Activate managed entities and children, then open the action servers."""
        result = super().on_activate(state)
        self._children("activate")
        self._set_active(True)
        return result

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Close the action servers, then deactivate children and managed entities."""
        self._set_active(False)
        self._children("deactivate")
        return super().on_deactivate(state)

    def on_cleanup(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Clean up the children."""
        self._children("cleanup")
        return super().on_cleanup(state)

    def on_shutdown(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Close the action servers for good; shut the children down."""
        self._set_active(False)
        self._children("shutdown")
        return super().on_shutdown(state)

    def accept_when_active(self, request: Any) -> GoalResponse:
        """Goal callback: ACCEPT when active, else REJECT with Nav2's log line."""
        if self.active:
            return GoalResponse.ACCEPT
        self.get_logger().info("Action server is inactive. Rejecting the goal.")
        return GoalResponse.REJECT

    def action_server(self, action_type: Any, name: str, execute: Callable[[Any], Any],
                      goal_callback: Callable[[Any], GoalResponse] | None = None
                      ) -> ActionServer:
        """Create an action server on this node that refuses goals unless ACTIVE.

        Args:
            action_type: The action type.
            name: Action name (relative: resolved in the node's namespace).
            execute: The execute callback.
            goal_callback: Further checks, run only when active.
        """

        def on_goal(request: Any) -> GoalResponse:
            response = self.accept_when_active(request)
            if response is GoalResponse.ACCEPT and goal_callback is not None:
                return goal_callback(request)
            return response

        return ActionServer(self, action_type, name, execute_callback=execute,
                            goal_callback=on_goal,
                            cancel_callback=lambda _handle: CancelResponse.ACCEPT,
                            callback_group=self.group)
