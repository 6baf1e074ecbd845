"""Start and stop ROS nodes in child processes, with the venv's interpreter.

The ROS wheels' ``.pth`` bootstrapper re-executes every interpreter of the venv once
with the right ``LD_LIBRARY_PATH``, so a child must be started with ``sys.executable``
of the test run (the venv's Python), never a system ``python3``.

Typical use::

    with NodeProcess(["-m", "sar_framework.sim"], "sim") as p:
        p.wait_for_output("ready", timeout=15)
        ...
    # leaving the block sends SIGINT, then SIGKILL if the node does not stop
"""

from __future__ import annotations

import os
import re
import sys
import tempfile
import time
from collections.abc import Sequence
from pathlib import Path
from types import TracebackType

from sar_framework.child_process import ChildProcess


class NodeProcess(ChildProcess):
    """A child Python process running a ROS node, its output captured to a file.

    The :class:`~sar_framework.child_process.ChildProcess` that ``sar-tree run`` starts its
    children with, plus what a test wants: the venv's interpreter, the test run's
    environment, :meth:`wait_for_output`, and a ``with`` block that stops it.

    Args:
        args: Arguments after the interpreter (``["-m", "pkg.module", ...]`` or a script).
        label: A short name for messages and the log file.
        env: Extra environment variables (the test run's ROS settings are inherited).
        log_dir: Where the output file goes (a temp dir by default).
        prefix: A command that runs the interpreter (``["ip", "netns", "exec", "ns1"]``).
    """

    def __init__(self, args: Sequence[str], label: str, *, env: dict[str, str] | None = None,
                 log_dir: Path | None = None, prefix: Sequence[str] = ()) -> None:
        folder = log_dir or Path(tempfile.mkdtemp(prefix="sar_node_"))
        super().__init__([*prefix, sys.executable, *args], label, env={**os.environ, **(env or {})},
                         log_path=folder / f"{label}.log")

    def start(self) -> NodeProcess:
        """Start the process (its own process group, so a stop reaches its children)."""
        super().start()
        return self

    def returncode(self) -> int | None:
        """The exit code, or None while it runs."""
        return self.poll()

    def wait_for_output(self, pattern: str, timeout: float = 20.0) -> re.Match[str]:
        """Wait until the output matches a regular expression.

        Args:
            pattern: The regular expression.
            timeout: Seconds to wait.

        Returns:
            The match.

        Raises:
            AssertionError: Timeout or the process ended first; the output is in the message.
        """
        deadline = time.monotonic() + timeout
        regex = re.compile(pattern)
        while True:
            match = regex.search(self.output)
            if match:
                return match
            if self.returncode() is not None:
                raise AssertionError(
                    f"{self.label} exited ({self.returncode()}) before printing {pattern!r}:\n"
                    f"{self.output}"
                )
            if time.monotonic() > deadline:  # outer safety bound
                raise AssertionError(
                    f"{self.label}: no {pattern!r} within {timeout} s:\n{self.output}"
                )
            time.sleep(0.05)

    def send_signal(self, sig: int) -> None:
        """Send a signal to the process group."""
        self.signal(sig)

    def __enter__(self) -> NodeProcess:
        return self.start()

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        self.stop()
