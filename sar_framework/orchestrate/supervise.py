"""Process supervision of ``sar-tree run``: children, their output, signals, stop order.

Each child runs ``sys.executable -m <module> --ros-args ...`` in a session of its own, so
a Ctrl-C in the terminal reaches only ``sar-tree run``, which then stops the runner first
(its running leaves cancel their goals while the simulator still serves), then the servers
and the simulator, and kills whatever is still alive after a bound. A child also receives
SIGTERM if ``sar-tree run`` dies without cleaning up (Linux ``PR_SET_PDEATHSIG``), so no
child outlives it. The process itself is a :class:`~sar_framework.child_process.ChildProcess`,
the wrapper the watcher and the test kit use too.
"""

from __future__ import annotations

import contextlib
import os
import re
import signal
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from sar_framework.child_process import ChildProcess
from sar_framework.events.jsonl import JsonLinesFollower
from sar_framework.orchestrate.config import ChildSpec

RUNNER_STOP_S = 1.2
"""Wall seconds the runner gets to cancel its goals and exit after SIGINT."""
OTHERS_STOP_S = 0.6
"""Wall seconds the servers and the simulator get after SIGINT before SIGKILL."""

GOAL_ENDS = frozenset({"canceled", "aborted", "succeeded"})
"""The simulator's trace events that end a goal (a stop may release the simulator then)."""

_ROS_LINE = re.compile(r"^\[(DEBUG|INFO|WARN|ERROR|FATAL)\] \[[0-9.]+\] \[([^\]]+)\]: (.*)$")


@dataclass
class LogLine:
    """One line a child printed.

    Attributes:
        child: The child's label.
        severity: ``INFO``, ``WARN``... or ``""`` for a line that is not a ROS log line.
        node: The ROS node's logger name (``""`` when not a ROS log line).
        message: The message (or the whole line).
        wall_s: Wall seconds since the mission started.
    """

    child: str
    severity: str
    node: str
    message: str
    wall_s: float


def start_child(spec: ChildSpec, env: dict[str, str], log_path: Path,
                on_line: Callable[[LogLine], None], started: float) -> ChildProcess:
    """Start one child of the mission: ``python -m MODULE --ros-args ...``.

    It runs in a session of its own and dies with this process; its output goes to
    ``log_path`` and, once :meth:`~ChildProcess.start_reading` is called, to ``on_line``
    as :class:`LogLine` (a line that is not a ROS log line keeps the last severity: the
    continuation of a multi-line message).

    Args:
        spec: What to run.
        env: Its environment.
        log_path: The log file (truncated).
        on_line: Called (from a reader thread) with every line.
        started: ``time.monotonic()`` of the mission start.
    """
    last = ["", ""]  # severity, node of the last ROS log line

    def parse(text: str) -> None:
        match = _ROS_LINE.match(text)
        if match:
            last[0], last[1], message = match.groups()
        else:
            message = text
        on_line(LogLine(spec.label, last[0], last[1], message, time.monotonic() - started))

    argv = [sys.executable, "-m", spec.module, "--ros-args", *spec.ros_args]
    if spec.python_path:
        env = {**env, "PYTHONPATH": os.pathsep.join(
            [*spec.python_path, *filter(None, [env.get("PYTHONPATH", "")])])}
    return ChildProcess(argv, spec.label, env=env, log_path=log_path, on_line=parse,
                        die_with_parent=True).start()


def stop_children(children: Sequence[ChildProcess], *, first: str = "runner", last: str = "sim",
                  released: Callable[[], bool] | None = None) -> float:
    """Stop children in order, SIGKILL after bounds; return the wall seconds it took.

    ``first`` (the runner) and every other child but ``last`` get SIGINT at once; ``last``
    (the simulator, which must still serve while the runner cancels its goal) gets it when
    ``first`` has exited or ``released`` returns true (the cancel went through), whichever
    comes first, at the latest after :data:`RUNNER_STOP_S`.

    Args:
        children: The children (some may have exited already).
        first: The label of the child whose exit releases ``last`` (every ``NS/first``
            too: a fleet's runners).
        last: The label of the child stopped last.
        released: Polled: true once ``last`` may stop early (e.g. its goal ended).
    """
    start = time.monotonic()
    early = [c for c in children if c.label != last]
    late = [c for c in children if c.label == last]
    leader = [c for c in children if c.label == first or c.label.endswith("/" + first)]
    for child in early:
        child.signal(signal.SIGINT)
    deadline = start + RUNNER_STOP_S
    while (time.monotonic() < deadline and any(c.poll() is None for c in leader)
           and not (released is not None and released())):
        time.sleep(0.01)
    for child in late:
        child.signal(signal.SIGINT)
    deadline = max(deadline, time.monotonic() + OTHERS_STOP_S)
    while time.monotonic() < deadline and any(c.poll() is None for c in children):
        time.sleep(0.01)
    for child in children:
        if child.poll() is None:
            child.signal(signal.SIGKILL)
    for child in children:
        with contextlib.suppress(subprocess.TimeoutExpired):
            child.wait(timeout=1.0)
    for child in children:
        child.finish_reading(timeout=0.5)
    return time.monotonic() - start


class GoalTraces:
    """The simulator's goals, from its trace files (one per robot), read as they grow.

    Args:
        paths: The trace files.
    """

    def __init__(self, paths: Sequence[Path]) -> None:
        self._traces = [JsonLinesFollower(path) for path in paths]
        self._in_flight = 0

    def _records(self) -> list[dict]:
        return [r for trace in self._traces for r in trace.poll() if isinstance(r, dict)]

    def in_flight(self) -> int:
        """Goals accepted and not yet ended, counted from the first call on."""
        for record in self._records():
            if record.get("event") == "accepted":
                self._in_flight += 1
            elif record.get("event") in GOAL_ENDS:
                self._in_flight = max(0, self._in_flight - 1)
        return self._in_flight

    def ended(self) -> bool:
        """Whether a goal ended since the last call."""
        return any(record.get("event") in GOAL_ENDS for record in self._records())
