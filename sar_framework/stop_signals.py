"""Stop a process on SIGINT or SIGTERM through a flag, never an exception where it lands.

The one "a signal sets a flag" helper of the project: the runner, the simulator, the
servers, the recorder, ``sar-tree watch`` and ``sar-tree run`` all stop through it. No
ROS is imported here.

rclpy's own handlers raise KeyboardInterrupt wherever the main thread is and shut the
context down under the executor (a take or a half-made Task then prints a traceback); our
ROS processes init rclpy with ``SignalHandlerOptions.NO`` and check the flag in their spin
loop. ``sar-tree run`` checks it in its wait loop, then stops its children in order.

A Ctrl-C usually arrives twice: a terminal (or ``killpg``) interrupts the whole process
group, and ``ros2 launch`` without a terminal on stdin (``--noninteractive``, its default
then) sends each child SIGINT once more. Once a process is stopping, a further SIGINT must
change nothing: the first stop signal makes the process ignore SIGINT from then on
(:func:`stopping`). Without it, the second SIGINT could land after Python's finalization
had put the default action back (it does so for every signal with a Python handler) and
end the process with -2 ("process has died" under launch, no traceback) although it was
stopping cleanly. SIGTERM keeps its handler: it is the escalation for a stop that takes
too long.
"""

from __future__ import annotations

import signal
import threading
from types import FrameType
from typing import Any

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)


class StopSignals:
    """SIGINT/SIGTERM recorded as a flag (true once one came) and an event to wait on.

    Attributes:
        received: The signal numbers received, in order (empty until one comes).
        event: Set by the first one (``event.wait(timeout)`` in a loop that sleeps).
    """

    def __init__(self) -> None:
        self.received: list[int] = []
        self.event = threading.Event()
        self._previous: dict[int, Any] = {}

    def install(self) -> StopSignals:
        """Install the handlers (main thread only), keeping the ones replaced; return self."""
        for sig in STOP_SIGNALS:
            self._previous[sig] = signal.signal(sig, self._handle)
        return self

    def restore(self) -> None:
        """Put back the handlers :meth:`install` replaced."""
        for sig, handler in self._previous.items():
            signal.signal(sig, handler)
        self._previous.clear()

    def __bool__(self) -> bool:
        """Whether a stop signal came."""
        return bool(self.received)

    @property
    def name(self) -> str:
        """The first signal's name (``SIGINT``), or ``""`` before any came."""
        return signal.Signals(self.received[0]).name if self.received else ""

    def _handle(self, signum: int, _frame: FrameType | None) -> None:
        if not self.received:
            stopping()
        self.received.append(signum)
        self.event.set()


def stopping() -> None:
    """Ignore SIGINT from now on: the first stop signal calls it."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def stop_on_signals() -> StopSignals:
    """Install the stop handlers (main thread only).

    Returns:
        The flag: false until SIGINT or SIGTERM comes; :meth:`StopSignals.restore` puts
        the previous handlers back.
    """
    return StopSignals().install()
