"""Stop a ROS process on SIGINT or SIGTERM through a flag, never an exception inside rclpy.

rclpy's own handlers raise KeyboardInterrupt wherever the main thread is and shut the
context down under the executor (a take or a half-made Task then prints a traceback); our
processes init rclpy with ``SignalHandlerOptions.NO`` and check the flag in their spin loop.
"""

from __future__ import annotations

import signal
from typing import Any

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)


def stop_on_signals() -> tuple[list[int], dict[int, Any]]:
    """Install handlers that record each stop signal instead of raising.

    Returns:
        ``(stop, previous)``: the signal numbers received (empty until one comes) and the
        handlers replaced, for a caller that restores them.
    """
    stop: list[int] = []
    previous = {sig: signal.signal(sig, lambda signum, _frame: stop.append(signum))
                for sig in STOP_SIGNALS}
    return stop, previous
