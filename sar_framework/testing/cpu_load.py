"""CPU load for soaks: busy-loop processes that keep cores busy, each bounded in time."""

from __future__ import annotations

import subprocess
import sys

_BURN = "import time\nend = time.monotonic() + {bound}\nwhile time.monotonic() < end:\n    pass\n"


def start_burners(count: int, bound_s: float) -> list[subprocess.Popen[bytes]]:
    """Start ``count`` processes that each keep one core busy for at most ``bound_s`` seconds.

    Args:
        count: How many (one per core loads the whole machine).
        bound_s: The longest a burner runs if nobody stops it.

    Returns:
        The burners; stop them with :func:`stop_burners`.
    """
    return [subprocess.Popen([sys.executable, "-c", _BURN.format(bound=bound_s)])
            for _ in range(count)]


def stop_burners(burners: list[subprocess.Popen[bytes]]) -> None:
    """Kill the burners (by their own pids) and reap them.

    Args:
        burners: What :func:`start_burners` returned.
    """
    for burner in burners:
        if burner.poll() is None:
            burner.kill()
    for burner in burners:
        burner.wait(timeout=10)
