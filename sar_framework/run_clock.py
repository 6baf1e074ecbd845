"""The run's wall-clock origin: the instant ``sar-tree run`` started, shared with its children.

Every ``wall_s`` a run writes (progress lines, ``events.jsonl``, ``status.json``) counts
seconds from one instant, so a reader puts the runner's first tick and the orchestrator's
stop on one time line. ``sar-tree run`` takes its own process's start as the origin and
hands it to its children in :data:`RUN_STARTED_ENV`, on ``time.monotonic()``'s clock
(``CLOCK_MONOTONIC``, one clock for every process of the machine). A runner started any
other way (``ros2 launch``, a test) counts from its own start. No ROS is imported here.
"""

from __future__ import annotations

import os
import time
from collections.abc import Mapping
from pathlib import Path

RUN_STARTED_ENV = "SAR_RUN_STARTED"
"""The environment variable holding the run's origin, ``time.monotonic()`` seconds."""


def process_started() -> float:
    """This process's creation instant on ``time.monotonic()``'s clock (now, if unknown).

    Linux gives it in ``/proc/self/stat`` (field 22, clock ticks since boot, on the boot-time
    clock); elsewhere the answer is the moment of the call.
    """
    now = time.monotonic()
    try:
        stat = Path("/proc/self/stat").read_text()
        ticks = int(stat.rsplit(")", 1)[1].split()[19])  # fields after "pid (comm)": 3..
        since_start = time.clock_gettime(time.CLOCK_BOOTTIME) - ticks / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, IndexError, AttributeError):
        return now
    return now - since_start if 0.0 <= since_start < 3600.0 else now


def run_started(environ: Mapping[str, str] | None = None) -> float:
    """The run's origin: what ``sar-tree run`` handed down, else the moment of the call.

    Args:
        environ: The environment to read (``os.environ`` by default).
    """
    now = time.monotonic()
    text = (os.environ if environ is None else environ).get(RUN_STARTED_ENV, "")
    try:
        origin = float(text)
    except ValueError:
        return now
    return origin if 0.0 <= now - origin < 3600.0 else now  # a stale or foreign value: ours
