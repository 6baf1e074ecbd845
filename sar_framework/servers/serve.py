"""Run one server node until SIGINT: the shared ``main`` of the mission's servers."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from rclpy.node import Node

#: Exit code for a configuration the server cannot start with.
EXIT_CONFIG = 2


class ServerConfigError(ValueError):
    """Raised by a server's constructor for a configuration it cannot serve with."""


def serve(make_node: Callable[[], Node], logger_name: str,
          argv: Sequence[str] | None = None) -> int:
    """Initialise rclpy, build the node, spin it until SIGINT and shut down cleanly.

    Args:
        make_node: Builds the server node (after ``rclpy.init``); may raise
            :class:`ServerConfigError` or ``ValueError`` for a bad configuration.
        logger_name: Logger for a start-up error (the node may not exist yet).
        argv: Command line (``sys.argv`` when None); ROS arguments are honoured.

    Returns:
        The process exit code: 0 after SIGINT, 2 for a bad configuration.
    """
    import signal
    import sys

    import rclpy
    from rclpy.executors import ExternalShutdownException

    from sar_framework.recording.introspection import enable_service_introspection

    rclpy.init(args=list(sys.argv if argv is None else argv))
    node = None
    try:
        try:
            node = make_node()
        except ValueError as err:  # ServerConfigError, and rclpy's bad-parameter errors
            rclpy.logging.get_logger(logger_name).error(str(err))
            return EXIT_CONFIG
        enable_service_introspection(node)
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        # Under ros2 launch a Ctrl-C arrives twice (the terminal's process group, then
        # launch): a second KeyboardInterrupt in the clean-up printed a traceback, exit -2.
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
    return 0
