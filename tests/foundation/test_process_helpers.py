"""The one child-process wrapper and the one stop-signal flag, on real processes."""

from __future__ import annotations

import os
import signal
import sys
import time
from pathlib import Path

from sar_framework.child_process import ChildProcess
from sar_framework.stop_signals import stop_on_signals

IGNORES_SIGINT = ("import signal, time\n"
                  "signal.signal(signal.SIGINT, signal.SIG_IGN)\n"
                  "print('up', flush=True)\n"
                  "time.sleep(60)\n")


def test_a_stop_signal_sets_the_flag_and_the_handlers_come_back() -> None:
    before = {sig: signal.getsignal(sig) for sig in (signal.SIGINT, signal.SIGTERM)}
    stop = stop_on_signals()
    try:
        assert not stop and stop.name == ""
        os.kill(os.getpid(), signal.SIGTERM)
        os.kill(os.getpid(), signal.SIGINT)  # once stopping, SIGINT is ignored
        os.kill(os.getpid(), signal.SIGTERM)  # a SIGTERM is still seen (the escalation)
        assert stop and stop.name == "SIGTERM" and stop.event.is_set()
        assert stop.received == [signal.SIGTERM, signal.SIGTERM]
    finally:
        stop.restore()
    assert {sig: signal.getsignal(sig) for sig in before} == before


def test_piped_output_reaches_the_log_and_the_callback(tmp_path: Path) -> None:
    lines: list[str] = []
    child = ChildProcess([sys.executable, "-c", "print('one'); print('two')"], "echo",
                         log_path=tmp_path / "echo.log", on_line=lines.append).start()
    child.start_reading()
    assert child.wait(20) == 0
    child.finish_reading(5)
    assert lines == ["one", "two"]
    assert child.output == "one\ntwo\n"


def test_a_child_that_ignores_sigint_is_killed_after_the_bound(tmp_path: Path) -> None:
    child = ChildProcess([sys.executable, "-c", IGNORES_SIGINT], "stubborn",
                         log_path=tmp_path / "stubborn.log").start()
    while "up" not in child.output:
        assert child.poll() is None, child.output
        time.sleep(0.05)
    assert child.stop(timeout=0.5) == -signal.SIGKILL


def test_a_child_that_ends_by_itself_within_the_grace_is_not_signalled() -> None:
    child = ChildProcess([sys.executable, "-c", "pass"], "quick", own_group=False).start()
    assert child.stop(timeout=0.5, grace_s=20) == 0
