"""Run the upstream ``ros2`` command line (from the real Jazzy overlay) in tests."""

from __future__ import annotations

import shutil
import subprocess
import sys
import time
from pathlib import Path


def ros2_executable() -> str | None:
    """The venv's ``ros2`` script, or None where ros2cli is not installed."""
    return shutil.which("ros2", path=str(Path(sys.executable).parent))


def run_ros2(*args: str, expect: str = "", timeout: float = 30.0) -> str:
    """Run ``ros2 ARGS --no-daemon`` until it succeeds and prints ``expect``; return stdout.

    Each run discovers the graph afresh (no daemon left behind), so a first run may not
    see every node or topic yet: it is retried until ``timeout``.

    Raises:
        AssertionError: It never succeeded; the message holds its last output.
    """
    executable = ros2_executable()
    assert executable is not None, "the ros2 command line is not installed here"
    deadline = time.monotonic() + timeout
    while True:
        done = subprocess.run([sys.executable, executable, *args, "--no-daemon"],
                              capture_output=True, text=True, timeout=timeout, check=False)
        if (done.returncode == 0 and expect in done.stdout) or time.monotonic() > deadline:
            break
        time.sleep(0.5)
    assert done.returncode == 0 and expect in done.stdout, done.stdout + done.stderr
    return done.stdout
