"""Run the upstream ``ros2`` command line (from the real Jazzy overlay) in tests."""

from __future__ import annotations

import shutil
import subprocess
import sys
import time
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path


def ros2_executable() -> str | None:
    """The venv's ``ros2`` script, or None where ros2cli is not installed."""
    return shutil.which("ros2", path=str(Path(sys.executable).parent))


def attempt(command: Sequence[str], hang_s: float) -> subprocess.CompletedProcess[str] | None:
    """Run one ``ros2`` command; None when it hung past ``hang_s`` (it is killed then).

    A ``--no-daemon`` command spinning 3 s has been seen, once in many CI runs under load,
    still running 60 s later (a known ros2cli symptom). The callers ask again instead: the
    graph they wait for is not what hung.
    """
    try:
        return subprocess.run(command, capture_output=True, text=True, timeout=hang_s,
                              check=False)
    except subprocess.TimeoutExpired:
        return None


def run_ros2(*args: str, expect: str = "", timeout: float = 30.0, daemon: bool = False) -> str:
    """Run ``ros2 ARGS`` until it succeeds and prints ``expect``; return stdout.

    Without ``daemon`` it runs with ``--no-daemon``: each run discovers the graph afresh (no
    daemon left behind), so a first run may not see every node or topic yet. With
    ``daemon`` it asks the daemon :func:`ros2_daemon` runs, as ``ros2`` does by default. It
    is retried until ``timeout`` either way.

    Raises:
        AssertionError: It never succeeded; the message holds its last output.
    """
    executable = ros2_executable()
    assert executable is not None, "the ros2 command line is not installed here"
    command = [sys.executable, executable, *args] + ([] if daemon else ["--no-daemon"])
    deadline = time.monotonic() + timeout
    while True:
        done = attempt(command, hang_s=timeout)
        succeeded = done is not None and done.returncode == 0 and expect in done.stdout
        if succeeded or time.monotonic() > deadline:  # outer safety bound
            break
        time.sleep(0.5)
    assert done is not None, f"{' '.join(args)} hung past {timeout} s"
    assert succeeded, done.stdout + done.stderr
    return done.stdout


@contextmanager
def ros2_daemon() -> Iterator[None]:
    """Run the ``ros2`` daemon of this process's domain for the block, stopped afterwards.

    The daemon keeps discovering the graph between commands, so a command asks it for node
    names instead of spinning ``--spin-time`` and starting over when discovery was slow.
    """
    executable = ros2_executable()
    assert executable is not None, "the ros2 command line is not installed here"
    subprocess.run([sys.executable, executable, "daemon", "start"], capture_output=True,
                   text=True, timeout=60, check=True)
    try:
        yield
    finally:
        subprocess.run([sys.executable, executable, "daemon", "stop"], capture_output=True,
                       text=True, timeout=60, check=False)
