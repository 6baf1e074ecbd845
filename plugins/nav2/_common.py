"""What Nav2's BT nodes share: the basic ports, the navigator's defaults, poses, counters.

Nav2's nodes read some settings from the BT navigator rather than from their ports:
``default_server_timeout`` (20 ms), ``wait_for_service_timeout`` (1000 ms),
``robot_base_frame`` (``base_link``), ``global_frame`` (``map``), ``odom_topic``
(``odom``, IsStuck's odometry). Here they are the ROS parameters of the node given to
``setup(node=...)`` when it declares them, else Nav2's defaults. No ROS package is
imported at module level.
"""

from __future__ import annotations

import math
import time
from typing import TYPE_CHECKING, Any

from py_trees.blackboard import Blackboard

from sar_framework.engine.ports import InputPort, Port

if TYPE_CHECKING:
    from rclpy.node import Node

#: Nav2's BT navigator defaults, by parameter name.
NAVIGATOR_DEFAULTS: dict[str, Any] = {
    "default_server_timeout": 20,
    "wait_for_service_timeout": 1000,
    "robot_base_frame": "base_link",
    "global_frame": "map",
    "odom_topic": "odom",
}

_TIMEOUT_TEXT = ("{what} server timeout (ms). If not provided, uses the BT Navigator's "
                 "`default_server_timeout` parameter value (20 ms by default).")


def server_ports(default_name: str, *, action: bool = True) -> list[Port]:
    """``server_name`` and ``server_timeout``, the two ports every Nav2 action node has.

    Args:
        default_name: The server Nav2 talks to when ``server_name`` is not given.
        action: Whether the server is an action server (else a service server).
    """
    what = "Action" if action else "Service"
    return [
        InputPort("server_name", str, optional=True,
                  description=f"{what} server name. If not specified, `{default_name}` is used."),
        timeout_port(what),
    ]


def timeout_port(what: str = "Service") -> Port:
    """The ``server_timeout`` port alone (Nav2's service nodes and conditions)."""
    return InputPort("server_timeout", int, optional=True,
                     description=_TIMEOUT_TEXT.format(what=what))


def optional_input(ports: Any, name: str, fallback: Any = None) -> Any:
    """BT.CPP's ``getInput``: the port's value, or ``fallback`` when it has none."""
    if ports is None:
        return fallback
    try:
        return ports.get(name)
    except KeyError:
        return fallback


def navigator_setting(node: Node | None, name: str) -> Any:
    """The BT navigator's setting ``name``: the node's parameter if declared, else Nav2's."""
    if node is not None and node.has_parameter(name):
        value = node.get_parameter(name).value
        if value is not None:
            return value
    return NAVIGATOR_DEFAULTS[name]


def server_timeout_s(node: Node | None, ports: Any) -> float:
    """``server_timeout`` in seconds: the port (ms), else ``default_server_timeout``."""
    ms = optional_input(ports, "server_timeout")
    if ms is None:
        ms = navigator_setting(node, "default_server_timeout")
    return float(ms) / 1000.0


def wait_for_service_s(node: Node | None) -> float:
    """The navigator's ``wait_for_service_timeout`` in seconds."""
    return float(navigator_setting(node, "wait_for_service_timeout")) / 1000.0


def server_missing(node: Node | None, started: float, now: float, server: str) -> str | None:
    """The failure of a leaf still without its server once ``wait_for_service_timeout`` passed.

    Args:
        node: The ROS node whose parameters hold the navigator's settings.
        started: When the leaf started waiting (``time.monotonic()``).
        now: The time now (``time.monotonic()``).
        server: The server as the message names it (``"spin" action server``).

    Returns:
        The message to fail with, or None while the leaf may still wait.
    """
    bound = wait_for_service_s(node)
    if now - started > bound:
        return f"{server} not available after waiting for {bound:g} s"
    return None


def node_now(node: Node | None) -> float:
    """The node's clock in seconds (ROS time: simulated with ``use_sim_time``), else wall."""
    if node is None:
        return time.monotonic()
    return node.get_clock().now().nanoseconds / 1e9


def count_recovery() -> None:
    """Add one to the root blackboard's ``number_recoveries`` (Nav2's recovery counter)."""
    key = "/number_recoveries"
    Blackboard.set(key, int(Blackboard.storage.get(key, 0)) + 1)


def yaw_of(orientation: Any) -> float:
    """The yaw (radians) of a ``geometry_msgs/Quaternion``."""
    q = orientation
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def planar_distance(a: Any, b: Any) -> float:
    """Distance in the plane between two ``PoseStamped`` (or ``Pose``) messages."""
    pa = getattr(a, "pose", a).position
    pb = getattr(b, "pose", b).position
    return math.hypot(pa.x - pb.x, pa.y - pb.y)


def duration_msg(seconds: float) -> Any:
    """A ``builtin_interfaces/Duration`` of ``seconds``."""
    from builtin_interfaces.msg import Duration

    whole = math.floor(seconds)
    return Duration(sec=int(whole), nanosec=round((seconds - whole) * 1e9) % 1_000_000_000)
