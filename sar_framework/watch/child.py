"""``sar-tree run --watch``: ``sar-tree watch`` as a child drawing in the run's terminal.

The watcher shares the terminal (and its process group, so Ctrl-C reaches it too) while
``sar-tree run`` keeps its progress lines to itself; it ends by itself when the mission is
over or the runner has gone, and :func:`stop_watcher` bounds the wait.
"""

from __future__ import annotations

import sys

from sar_framework.child_process import ChildProcess

#: Seconds the watcher waits for the first tick (the runner's start-up included).
FIRST_TICK_WAIT_S = 120.0


def start_watcher(env: dict[str, str]) -> ChildProcess:
    """Start ``sar-tree watch`` on the mission's ROS domain, in this terminal.

    Args:
        env: The environment of the mission's children (same ``ROS_DOMAIN_ID``).
    """
    argv = [sys.executable, "-m", "sar_framework", "watch", "--wait", f"{FIRST_TICK_WAIT_S:g}"]
    return ChildProcess(argv, "watch", env=env, own_group=False).start()


def stop_watcher(watcher: ChildProcess, timeout_s: float = 3.0) -> int | None:
    """Wait for the watcher to end (SIGINT, then SIGKILL, each after ``timeout_s``)."""
    return watcher.stop(timeout_s, grace_s=timeout_s)
