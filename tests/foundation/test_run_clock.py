"""The run's wall-clock origin: sar-tree run's start, handed to its children."""

from __future__ import annotations

import subprocess
import sys
import time

from sar_framework.run_clock import RUN_STARTED_ENV, process_started, run_started


def test_the_origin_handed_down_is_used() -> None:
    origin = time.monotonic() - 2.5
    assert run_started({RUN_STARTED_ENV: repr(origin)}) == origin


def test_a_missing_garbled_future_or_stale_origin_is_the_moment_of_the_call() -> None:
    for text in ("", "soon", repr(time.monotonic() + 60.0), repr(time.monotonic() - 86400.0)):
        before = time.monotonic()
        assert before <= run_started({RUN_STARTED_ENV: text}) <= time.monotonic(), text


def test_a_process_start_is_before_its_first_line_and_after_its_parent_forked_it() -> None:
    forked = time.monotonic()
    done = subprocess.run(
        [sys.executable, "-c", "import time\nfrom sar_framework.run_clock import "
         "process_started\nprint(process_started(), time.monotonic())"],
        capture_output=True, text=True, check=True)
    started, first_line = map(float, done.stdout.split())
    # /proc counts in clock ticks (10 ms): the start may read up to one tick early
    assert forked - 0.011 <= started <= first_line, done.stdout


def test_this_process_started_before_now() -> None:
    assert process_started() <= time.monotonic()
