"""The run's wall-clock origin: sar-tree run's start, handed to its children.

The clock is fixed (``time.monotonic`` reads 1000 s), so each case is exact arithmetic on a
known instant rather than a comparison with a clock that moves.
"""

from __future__ import annotations

import time
from pathlib import Path

import pytest

from sar_framework import run_clock
from sar_framework.run_clock import RUN_STARTED_ENV, process_started, run_started

NOW = 1000.0


@pytest.fixture(autouse=True)
def fixed_clock(monkeypatch: pytest.MonkeyPatch) -> None:
    """``time.monotonic`` reads :data:`NOW` inside run_clock."""
    monkeypatch.setattr(run_clock.time, "monotonic", lambda: NOW)


def test_the_origin_handed_down_is_used() -> None:
    assert run_started({RUN_STARTED_ENV: repr(NOW - 2.5)}) == NOW - 2.5


@pytest.mark.parametrize("text", ["", "soon", repr(NOW + 60.0), repr(NOW - 86400.0)],
                         ids=["missing", "garbled", "future", "stale"])
def test_a_missing_garbled_future_or_stale_origin_is_the_moment_of_the_call(text: str) -> None:
    assert run_started({RUN_STARTED_ENV: text}) == NOW


def _stat(start_ticks: int) -> str:
    """A /proc/self/stat line whose field 22 (starttime) is ``start_ticks``."""
    fields = ["S"] + ["0"] * 18 + [str(start_ticks)] + ["0"] * 10  # fields 3..
    return "4242 (python (test)) " + " ".join(fields)


def test_a_process_start_is_read_from_proc_on_the_monotonic_clock(monkeypatch) -> None:
    # booted 50 s ago on the boot-time clock, started 40 s after boot (4000 ticks of 10 ms)
    monkeypatch.setattr(run_clock.time, "clock_gettime", lambda clock: 50.0)
    monkeypatch.setattr(run_clock.os, "sysconf", lambda name: 100)
    monkeypatch.setattr(Path, "read_text", lambda self, *a, **k: _stat(4000))
    assert process_started() == pytest.approx(NOW - 10.0)


def test_an_unreadable_or_implausible_start_is_the_moment_of_the_call(monkeypatch) -> None:
    monkeypatch.setattr(run_clock.time, "clock_gettime", lambda clock: 50.0)
    monkeypatch.setattr(run_clock.os, "sysconf", lambda name: 100)
    monkeypatch.setattr(Path, "read_text", lambda self, *a, **k: _stat(9000))  # after "now"
    assert process_started() == NOW
    monkeypatch.setattr(Path, "read_text", lambda self, *a, **k: "garbled")
    assert process_started() == NOW


def test_the_real_clock_is_read_when_nothing_is_fixed(monkeypatch) -> None:
    monkeypatch.undo()
    assert isinstance(process_started(), float) and isinstance(run_started({}), float)
    assert time.monotonic is run_clock.time.monotonic
