"""``sar-tree run --watch``: ``sar-tree watch`` as a child drawing in the run's terminal.

The watcher shares the terminal (and its process group, so Ctrl-C reaches it too) while
``sar-tree run`` keeps its progress lines to itself; it ends by itself when the mission is
over or the runner has gone, and :meth:`WatchChild.finish` bounds the wait.
"""

from __future__ import annotations

import contextlib
import signal
import subprocess
import sys

#: Seconds the watcher waits for the first tick (the runner's start-up included).
FIRST_TICK_WAIT_S = 120.0


class WatchChild:
    """A running ``sar-tree watch`` on the mission's ROS domain.

    Args:
        env: The environment of the mission's children (same ``ROS_DOMAIN_ID``).
    """

    def __init__(self, env: dict[str, str]) -> None:
        self.proc = subprocess.Popen(
            [sys.executable, "-m", "sar_framework", "watch", "--wait", f"{FIRST_TICK_WAIT_S:g}"],
            env=env, stdin=subprocess.DEVNULL)

    def finish(self, timeout_s: float = 3.0) -> int | None:
        """Wait for the watcher to end (SIGINT, then SIGKILL, after ``timeout_s``)."""
        for sig in (None, signal.SIGINT, signal.SIGKILL):
            if sig is not None and self.proc.poll() is None:
                self.proc.send_signal(sig)
            with contextlib.suppress(subprocess.TimeoutExpired):
                return self.proc.wait(timeout=timeout_s)
        return self.proc.poll()
