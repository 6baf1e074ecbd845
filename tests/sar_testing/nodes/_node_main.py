"""The shared tail of the fake nodes' ``main()``: spin until SIGINT, then clean up.

The nodes are run by path, so this folder is on ``sys.path`` and they import it as
``from _node_main import spin_until_interrupted``.
"""

from collections.abc import Callable
from typing import Any

import rclpy
from rclpy.executors import (
    ExternalShutdownException,
    MultiThreadedExecutor,
    SingleThreadedExecutor,
)
from rclpy.node import Node


def spin_until_interrupted(*nodes: Node, threads: int = 0) -> None:
    """Spin ``nodes`` until SIGINT or an external shutdown, then destroy them and shut down.

    Args:
        *nodes: The nodes to spin, all on one executor.
        threads: Threads of a MultiThreadedExecutor; 0 for a SingleThreadedExecutor.
    """
    executor = MultiThreadedExecutor(num_threads=threads) if threads else SingleThreadedExecutor()
    for node in nodes:
        executor.add_node(node)
    try:
        executor.spin()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        for node in nodes:
            node.destroy_node()
        rclpy.try_shutdown()


def serve_navigate_to_pose(node: Node, execute: Callable[[Any], Any], threads: int = 2) -> None:
    """Serve ``navigate_to_pose`` with ``execute``, accepting every goal and cancel.

    Logs ``ready`` once serving, then spins until SIGINT (see :func:`spin_until_interrupted`).

    Args:
        node: The node to serve on.
        execute: The action's execute callback.
        threads: Executor threads (a goal's callback blocks one while it runs).
    """
    from nav2_msgs.action import NavigateToPose
    from rclpy.action import ActionServer, CancelResponse, GoalResponse
    from rclpy.callback_groups import ReentrantCallbackGroup

    ActionServer(
        node, NavigateToPose, "navigate_to_pose", execute_callback=execute,
        goal_callback=lambda _goal: GoalResponse.ACCEPT,
        cancel_callback=lambda _handle: CancelResponse.ACCEPT,
        callback_group=ReentrantCallbackGroup(),
    )
    node.get_logger().info("ready")
    spin_until_interrupted(node, threads=threads)
