"""``lifecycle_manager_localization`` / ``lifecycle_manager_navigation``, as Nav2's.

Each manager brings its nodes up in order (configure, then activate) and down in reverse,
and serves ``~/manage_nodes`` (``nav2_msgs/srv/ManageLifecycleNodes``: STARTUP, PAUSE,
RESUME, RESET, SHUTDOWN) and ``~/is_active`` (``std_srvs/srv/Trigger``), which is what
``BasicNavigator.lifecycleStartup`` / ``lifecycleShutdown`` call. Bond-free: the nodes share
the manager's process, so the manager drives their transitions directly (each still
publishes its ``transition_event``). A transition a node cannot take (``configure`` on an
active node) fails the command, as in Nav2. Without the service types (fallback tier) the
manager offers neither service and only starts its nodes up.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Sequence
from typing import Any

from lifecycle_msgs.msg import State
from rclpy.node import Node

from sar_framework.sim.lifecycle import Nav2LifecycleNode, in_robot_namespace, optional_type

LOCALIZATION_NODES = ("map_server", "amcl")
"""Nav2 Jazzy ``localization_launch.py``'s managed nodes, in start-up order."""
NAVIGATION_NODES = ("controller_server", "smoother_server", "planner_server",
                    "behavior_server", "bt_navigator", "waypoint_follower")
"""Nav2 Jazzy ``navigation_launch.py``'s managed nodes that the simulator provides."""


def _transition(node: Nav2LifecycleNode, name: str, wanted: int) -> bool:
    """Run one transition; True if it succeeded and left the node in ``wanted``."""
    trigger: Callable[[], Any] = getattr(node, f"trigger_{name}")
    try:
        trigger()
    except Exception as exc:  # rclpy raises when the transition is not valid from here
        node.get_logger().error(f"Failed to {name}: {exc}")
        return False
    return node.state_id() == wanted


class LifecycleManager:
    """One Nav2 lifecycle manager over in-process lifecycle nodes.

    Args:
        name: ``lifecycle_manager_localization`` or ``lifecycle_manager_navigation``.
        nodes: The managed nodes, in start-up order.
    """

    def __init__(self, name: str, nodes: Sequence[Nav2LifecycleNode]) -> None:
        self.node = Node(name, namespace=in_robot_namespace())
        self.nodes = list(nodes)
        self._lock = threading.Lock()
        self.system_active = False
        self.node.declare_parameter("node_names", [n.get_name() for n in self.nodes])
        self.node.declare_parameter("autostart", True)
        manage = optional_type("nav2_msgs.srv", "ManageLifecycleNodes",
                               needed_by=f"{name}/manage_nodes")
        if manage is not None:
            self.node.create_service(manage, "~/manage_nodes", self._on_manage)
        trigger = optional_type("std_srvs.srv", "Trigger", needed_by=f"{name}/is_active")
        if trigger is not None:
            self.node.create_service(trigger, "~/is_active", self._on_is_active)

    @property
    def autostart(self) -> bool:
        """The ``autostart`` parameter (Nav2's bringup default: true)."""
        return bool(self.node.get_parameter("autostart").value)

    # ------------------------------------------------------------------ commands

    def startup(self) -> bool:
        """Configure, then activate, every node in order."""
        log = self.node.get_logger()
        log.info("Starting managed nodes bringup...")
        ok = self._all("configure", State.PRIMARY_STATE_INACTIVE) and \
            self._all("activate", State.PRIMARY_STATE_ACTIVE)
        self.system_active = ok
        log.info("Managed nodes are active" if ok else "Failed to bring up all requested nodes.")
        return ok

    def shutdown(self) -> bool:
        """Deactivate, clean up and shut down every node, in reverse order."""
        self.node.get_logger().info("Shutting down managed nodes...")
        self.system_active = False
        ok = True
        for node in reversed(self.nodes):
            state = node.state_id()
            if state == State.PRIMARY_STATE_ACTIVE:
                ok &= _transition(node, "deactivate", State.PRIMARY_STATE_INACTIVE)
            if node.state_id() == State.PRIMARY_STATE_INACTIVE:
                ok &= _transition(node, "cleanup", State.PRIMARY_STATE_UNCONFIGURED)
            if node.state_id() != State.PRIMARY_STATE_FINALIZED:
                ok &= _transition(node, "shutdown", State.PRIMARY_STATE_FINALIZED)
        self.node.get_logger().info("Managed nodes have been shut down")
        return ok

    def pause(self) -> bool:
        """Deactivate every node, in reverse order."""
        self.system_active = False
        return self._all("deactivate", State.PRIMARY_STATE_INACTIVE, reverse=True)

    def resume(self) -> bool:
        """Activate every node, in order."""
        self.system_active = self._all("activate", State.PRIMARY_STATE_ACTIVE)
        return self.system_active

    def reset(self) -> bool:
        """Deactivate and clean up every node, in reverse order."""
        self.system_active = False
        return self._all("deactivate", State.PRIMARY_STATE_INACTIVE, reverse=True) and \
            self._all("cleanup", State.PRIMARY_STATE_UNCONFIGURED, reverse=True)

    def _all(self, transition: str, wanted: int, *, reverse: bool = False) -> bool:
        for node in reversed(self.nodes) if reverse else self.nodes:
            if not _transition(node, transition, wanted):
                self.node.get_logger().error(
                    f"Failed to change state for node: {node.get_name()}")
                return False
        return True

    # ------------------------------------------------------------------ services

    def _on_manage(self, request: Any, response: Any) -> Any:
        commands = {
            request.STARTUP: self.startup, request.PAUSE: self.pause,
            request.RESUME: self.resume, request.RESET: self.reset,
            request.SHUTDOWN: self.shutdown,
        }
        command = commands.get(request.command)
        with self._lock:
            response.success = bool(command()) if command is not None else False
        return response

    def _on_is_active(self, _request: Any, response: Any) -> Any:
        response.success = self.system_active
        return response
