"""Process supervision of ``sar-tree run``: children, their output, signals, stop order.

Each child runs ``sys.executable -m <module> --ros-args ...`` in a session of its own, so
a Ctrl-C in the terminal reaches only ``sar-tree run``, which then stops the runner first
(its running leaves cancel their goals while the simulator still serves), then the servers
and the simulator, and kills whatever is still alive after a bound. A child also receives
SIGTERM if ``sar-tree run`` dies without cleaning up (Linux ``PR_SET_PDEATHSIG``), so no
child outlives it.
"""

from __future__ import annotations

import contextlib
import ctypes
import ctypes.util
import os
import re
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from types import FrameType
from typing import IO, Any

from sar_framework.orchestrate.config import ChildSpec

RUNNER_STOP_S = 1.2
"""Wall seconds the runner gets to cancel its goals and exit after SIGINT."""
OTHERS_STOP_S = 0.6
"""Wall seconds the servers and the simulator get after SIGINT before SIGKILL."""

_ROS_LINE = re.compile(r"^\[(DEBUG|INFO|WARN|ERROR|FATAL)\] \[[0-9.]+\] \[([^\]]+)\]: (.*)$")


def _parent_death_signal() -> Callable[[], None] | None:
    """A ``preexec_fn`` asking Linux to SIGTERM the child when this process dies."""
    if not sys.platform.startswith("linux"):
        return None
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
    except OSError:
        return None
    prctl = libc.prctl
    pr_set_pdeathsig = 1

    def preexec() -> None:
        prctl(pr_set_pdeathsig, int(signal.SIGTERM))

    return preexec


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


class Child:
    """A running child process whose output goes to a log file and to a line callback.

    Args:
        spec: What to run.
        env: Its environment.
        log_path: The log file (truncated).
        on_line: Called (from a reader thread) with every line.
        started: ``time.monotonic()`` of the mission start.
    """

    def __init__(self, spec: ChildSpec, env: dict[str, str], log_path: Path,
                 on_line: Callable[[LogLine], None], started: float) -> None:
        self.spec = spec
        self.log_path = log_path
        self._on_line = on_line
        self._started = started
        self._log: IO[str] = log_path.open("w", encoding="utf-8")
        self.proc = subprocess.Popen(
            [sys.executable, "-m", spec.module, "--ros-args", *spec.ros_args],
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
            env=env, start_new_session=True,
            # Safe here: Mission.start forks every child before any reader thread starts.
            preexec_fn=_parent_death_signal(),  # noqa: PLW1509
        )
        self._reader = threading.Thread(target=self._read, name=f"read-{spec.label}",
                                        daemon=True)

    @property
    def label(self) -> str:
        """The child's label."""
        return self.spec.label

    def start_reading(self) -> None:
        """Start the thread that copies the output to the log and the callback."""
        self._reader.start()

    def _read(self) -> None:
        assert self.proc.stdout is not None
        severity, node = "", ""
        for raw in iter(self.proc.stdout.readline, b""):
            text = raw.decode("utf-8", "replace").rstrip("\n")
            self._log.write(text + "\n")
            self._log.flush()
            match = _ROS_LINE.match(text)
            if match:
                severity, node, message = match.groups()
            else:
                message = text  # continuation of a multi-line message keeps its severity
            self._on_line(LogLine(self.label, severity, node, message,
                                  time.monotonic() - self._started))
        self._log.close()

    def poll(self) -> int | None:
        """The exit code, or None while it runs."""
        return self.proc.poll()

    def signal(self, sig: int) -> None:
        """Send ``sig`` to the child's process group (if it still runs)."""
        if self.proc.poll() is None:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(self.proc.pid, sig)

    def finish(self, timeout: float = 1.0) -> None:
        """Wait for the reader thread to drain the output."""
        self._reader.join(timeout=timeout)


def stop_children(children: Sequence[Child], *, first: str = "runner", last: str = "sim",
                  released: Callable[[], bool] | None = None) -> float:
    """Stop children in order, SIGKILL after bounds; return the wall seconds it took.

    ``first`` (the runner) and every other child but ``last`` get SIGINT at once; ``last``
    (the simulator, which must still serve while the runner cancels its goal) gets it when
    ``first`` has exited or ``released`` returns true (the cancel went through), whichever
    comes first, at the latest after :data:`RUNNER_STOP_S`.

    Args:
        children: The children (some may have exited already).
        first: The label of the child whose exit releases ``last``.
        last: The label of the child stopped last.
        released: Polled: true once ``last`` may stop early (e.g. its goal ended).
    """
    start = time.monotonic()
    early = [c for c in children if c.label != last]
    late = [c for c in children if c.label == last]
    leader = [c for c in children if c.label == first]
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
            child.proc.wait(timeout=1.0)
    for child in children:
        child.finish(timeout=0.5)
    return time.monotonic() - start


class Interrupt:
    """SIGINT/SIGTERM set an event the main loop polls (:meth:`install` in the main thread)."""

    def __init__(self) -> None:
        self.event = threading.Event()
        self.name = ""
        self._previous: dict[int, Any] = {}

    def install(self) -> None:
        """Install the handlers, keeping the previous ones."""
        for sig in (signal.SIGINT, signal.SIGTERM):
            self._previous[sig] = signal.signal(sig, self._handle)

    def restore(self) -> None:
        """Put the previous handlers back."""
        for sig, handler in self._previous.items():
            signal.signal(sig, handler)

    def _handle(self, signum: int, _frame: FrameType | None) -> None:
        self.name = signal.Signals(signum).name
        self.event.set()
