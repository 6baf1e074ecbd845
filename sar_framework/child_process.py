"""One child process: started, its output kept, signalled, stopped within a bound.

The one wrapper ``sar-tree run`` (its mission's processes and ``--watch``), and the test
kit (:class:`sar_framework.testing.processes.NodeProcess`) start their children with. No
ROS is imported here.

Where the output goes is chosen once, at construction:

- ``log_path`` alone: straight into that file (:attr:`ChildProcess.output` reads it);
- ``log_path`` and ``on_line``: through a pipe that a reader thread copies into the file
  and hands to ``on_line`` line by line (start it with :meth:`ChildProcess.start_reading`
  once every child is forked);
- neither: the parent's terminal (a child that draws there, like ``sar-tree watch``).

A child in a session of its own (``own_group``, the default) gets its signals as a group,
so a stop reaches whatever it started in turn, and a terminal's Ctrl-C reaches only the
parent, which then stops its children in the order it chooses. ``die_with_parent`` asks
Linux to SIGTERM the child if the parent dies without stopping it (``PR_SET_PDEATHSIG``).
"""

from __future__ import annotations

import contextlib
import ctypes
import functools
import os
import signal
import subprocess
import sys
import threading
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import IO


@functools.cache
def _parent_death_signal() -> Callable[[], None] | None:
    """A ``preexec_fn`` asking Linux to SIGTERM the child when this process dies.

    ``prctl`` is looked up among the symbols Python is already linked with (the C library),
    once a process: ``ctypes.util.find_library`` would run ``ldconfig`` for every child.
    """
    if not sys.platform.startswith("linux"):
        return None
    try:
        prctl = ctypes.CDLL(None, use_errno=True).prctl
    except (OSError, AttributeError):
        return None
    pr_set_pdeathsig = 1

    def preexec() -> None:
        prctl(pr_set_pdeathsig, int(signal.SIGTERM))

    return preexec


class ChildProcess:
    """A child process, its output and its stop.

    Args:
        argv: The command line (``[sys.executable, "-m", "pkg.module", ...]``).
        label: A short name for messages, threads and log files.
        env: Its whole environment (None: this process's).
        log_path: Where its output goes (truncated); None: this process's terminal.
        on_line: Called from a reader thread with every line of output (needs ``log_path``).
        own_group: Run it in a session (process group) of its own.
        die_with_parent: SIGTERM it when this process dies (Linux).
    """

    def __init__(self, argv: Sequence[str], label: str, *,
                 env: Mapping[str, str] | None = None, log_path: Path | None = None,
                 on_line: Callable[[str], None] | None = None, own_group: bool = True,
                 die_with_parent: bool = False) -> None:
        if on_line is not None and log_path is None:
            raise ValueError("on_line needs a log_path")
        self.argv = list(argv)
        self.label = label
        self.env = dict(os.environ if env is None else env)
        self.log_path = log_path
        self._on_line = on_line
        self._own_group = own_group
        self._die_with_parent = die_with_parent
        self.proc: subprocess.Popen[bytes] | None = None
        self._reader: threading.Thread | None = None

    def start(self) -> ChildProcess:
        """Start the process (output as chosen at construction); return ``self``."""
        preexec = _parent_death_signal() if self._die_with_parent else None
        common = {"env": self.env, "stdin": subprocess.DEVNULL,
                  "start_new_session": self._own_group,
                  # Safe: callers fork every child before any reader thread starts.
                  "preexec_fn": preexec}
        if self.log_path is None:
            self.proc = subprocess.Popen(self.argv, **common)
        elif self._on_line is None:
            with self.log_path.open("wb") as log:
                self.proc = subprocess.Popen(self.argv, stdout=log,
                                             stderr=subprocess.STDOUT, **common)
        else:
            self.proc = subprocess.Popen(self.argv, stdout=subprocess.PIPE,
                                         stderr=subprocess.STDOUT, **common)
            self._reader = threading.Thread(target=self._read, name=f"read-{self.label}",
                                            daemon=True)
        return self

    def start_reading(self) -> None:
        """Start the thread that copies piped output to the log and ``on_line``."""
        if self._reader is not None and not self._reader.is_alive():
            self._reader.start()

    def _read(self) -> None:
        assert self.proc is not None and self.proc.stdout is not None
        assert self.log_path is not None and self._on_line is not None
        log: IO[str]
        with self.log_path.open("w", encoding="utf-8") as log:
            for raw in iter(self.proc.stdout.readline, b""):
                text = raw.decode("utf-8", "replace").rstrip("\n")
                log.write(text + "\n")
                log.flush()
                self._on_line(text)

    @property
    def started(self) -> bool:
        """Whether :meth:`start` was called."""
        return self.proc is not None

    @property
    def pid(self) -> int:
        """The child's process id."""
        return self._proc().pid

    @property
    def output(self) -> str:
        """Everything written to the log file so far (empty without one)."""
        if self.log_path is None or not self.log_path.exists():
            return ""
        return self.log_path.read_text(errors="replace")

    def _proc(self) -> subprocess.Popen[bytes]:
        assert self.proc is not None, f"{self.label}: not started"
        return self.proc

    def poll(self) -> int | None:
        """The exit code, or None while it runs."""
        return self._proc().poll()

    def wait(self, timeout: float) -> int:
        """Wait for the process to end by itself; return its exit code.

        Raises:
            subprocess.TimeoutExpired: It still runs after ``timeout`` seconds.
        """
        return self._proc().wait(timeout=timeout)

    def signal(self, sig: int) -> None:
        """Send ``sig`` to the child (its whole group with ``own_group``) if it still runs."""
        proc = self._proc()
        if proc.poll() is None:
            with contextlib.suppress(ProcessLookupError):
                if self._own_group:
                    os.killpg(proc.pid, sig)
                else:
                    proc.send_signal(sig)

    def stop(self, timeout: float = 5.0, *, grace_s: float = 0.0) -> int | None:
        """End the child: ``grace_s`` to end by itself, SIGINT, then SIGKILL after ``timeout``.

        Args:
            timeout: Seconds after SIGINT (and after SIGKILL) before giving up waiting.
            grace_s: Seconds it may first take to end on its own.

        Returns:
            The exit code (None if it could not be reaped).
        """
        for sig, bound in ((None, grace_s), (signal.SIGINT, timeout), (signal.SIGKILL, timeout)):
            if sig is not None:
                self.signal(sig)
            with contextlib.suppress(subprocess.TimeoutExpired):
                return self.wait(bound)
        return self.poll()

    def finish_reading(self, timeout: float = 1.0) -> None:
        """Wait for the reader thread (if any) to drain the output."""
        if self._reader is not None and self._reader.is_alive():
            self._reader.join(timeout=timeout)
