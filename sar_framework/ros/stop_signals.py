"""Stop a ROS process on SIGINT or SIGTERM through a flag, never an exception inside rclpy.

rclpy's own handlers raise KeyboardInterrupt wherever the main thread is and shut the
context down under the executor (a take or a half-made Task then prints a traceback); our
processes init rclpy with ``SignalHandlerOptions.NO`` and check the flag in their spin loop.

A Ctrl-C usually arrives twice: a terminal (or ``killpg``) interrupts the whole process
group, and ``ros2 launch`` without a terminal on stdin (``--noninteractive``, its default
then) sends each child SIGINT once more. Once a process is stopping, a further SIGINT must
change nothing: :func:`stopping` ignores SIGINT from then on. Without it, the second SIGINT
could land after Python's finalization had put the default action back (it does so for
every signal with a Python handler) and end the process with -2 ("process has died" under
launch, no traceback) although it was stopping cleanly. SIGTERM keeps its handler: it is
the escalation for a stop that takes too long.
"""

from __future__ import annotations

import signal
from typing import Any

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)


def stopping() -> None:
    """Ignore SIGINT from now on: call it from a handler on the first stop signal."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def stop_on_signals() -> tuple[list[int], dict[int, Any]]:
    """Install handlers that record each stop signal instead of raising.

    The first stop signal also calls :func:`stopping`.

    Returns:
        ``(stop, previous)``: the signal numbers received (empty until one comes) and the
        handlers replaced, for a caller that restores them.
    """
    stop: list[int] = []

    def record(signum: int, _frame: object) -> None:
        if not stop:
            stopping()
        stop.append(signum)

    previous = {sig: signal.signal(sig, record) for sig in STOP_SIGNALS}
    return stop, previous
