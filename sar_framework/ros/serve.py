"""Run one server node until SIGINT: the shared ``main`` of the mission's servers."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

from sar_framework.ros.teardown import TEARDOWN_BOUND_S

if TYPE_CHECKING:
    from rclpy.node import Node

#: Exit code for a configuration the server cannot start with.
EXIT_CONFIG = 2
#: Longest wait of one spin: how long a signal may wait to be noticed.
SPIN_TIMEOUT_S = 0.1


class ServerConfigError(ValueError):
    """Raised by a server's constructor for a configuration it cannot serve with."""


def serve(make_node: Callable[[], Node], logger_name: str,
          argv: Sequence[str] | None = None,
          teardown_bound_s: float = TEARDOWN_BOUND_S) -> int:
    """Initialise rclpy, build the node, spin it until SIGINT and shut down cleanly.

    Args:
        make_node: Builds the server node (after ``rclpy.init``); may raise
            :class:`ServerConfigError` or ``ValueError`` for a bad configuration.
        logger_name: Logger for a start-up error (the node may not exist yet).
        argv: Command line (``sys.argv`` when None); ROS arguments are honoured.
        teardown_bound_s: Wall seconds after which a teardown still running prints every
            thread's stack to stderr and ends the process
            (:func:`~sar_framework.ros.teardown.bounded_teardown`).

    Returns:
        The process exit code: 0 after SIGINT or SIGTERM, 2 for a bad configuration.
    """
    import sys

    import rclpy
    from rclpy.experimental import EventsExecutor
    from rclpy.signals import SignalHandlerOptions

    from sar_framework.ros.introspection import enable_service_introspection
    from sar_framework.ros.teardown import bounded_teardown
    from sar_framework.stop_signals import stop_on_signals

    stop = stop_on_signals()  # a flag the spin loop checks, not rclpy's handlers
    rclpy.init(args=list(sys.argv if argv is None else argv),
               signal_handler_options=SignalHandlerOptions.NO)
    node = None
    try:
        try:
            node = make_node()
        except ValueError as err:  # ServerConfigError, and rclpy's bad-parameter errors
            rclpy.logging.get_logger(logger_name).error(str(err))
            return EXIT_CONFIG
        enable_service_introspection(node)
        # rclpy's events executor (in Jazzy's rclpy since 7.1): each /clock message costs a
        # server less than half the CPU it does with the SingleThreadedExecutor's per-wake-up
        # wait set (about 4 % of a core instead of 9, at the simulator's 100 Hz then).
        executor = EventsExecutor()
        executor.add_node(node)
        while not stop:
            executor.spin_once(timeout_sec=SPIN_TIMEOUT_S)
        executor.shutdown(timeout_sec=0.0)
    finally:
        with bounded_teardown(teardown_bound_s):  # Fast DDS's participant teardown can hang
            if node is not None:
                node.destroy_node()
            rclpy.try_shutdown()
    return 0
