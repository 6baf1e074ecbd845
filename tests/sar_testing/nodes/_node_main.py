"""The shared tail of the fake nodes' ``main()``: spin until SIGINT, then clean up.

The nodes are run by path, so this folder is on ``sys.path`` and they import it as
``from _node_main import spin_until_interrupted``.
"""

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
