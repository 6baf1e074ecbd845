"""Ctrl-C mid-mission: the goal in flight is cancelled and every process ends quickly."""

from __future__ import annotations

import signal
import time

import pytest

from .helpers import DEFAULT_TREE, child_pids, read_jsonl, sar_tree_run, wait_gone

pytestmark = [pytest.mark.slow, pytest.mark.ros]

EXIT_BOUND_S = 5.0  # generous for a loaded CI machine; the benchmark measures the real figure


def test_sigint_mid_navigation_cancels_the_goal_and_exits_quickly(tmp_path) -> None:
    report = tmp_path / "report"
    process = sar_tree_run([str(DEFAULT_TREE), "--speed", "2"], report)
    try:
        process.wait_for_output(r"--- Zone 1/4: zone_a", timeout=60)
        children = child_pids(process.pid)
        assert len(children) == 4
        time.sleep(0.5)
        start = time.monotonic()
        process.send_signal(signal.SIGINT)
        code = process.wait(timeout=15)
        elapsed = time.monotonic() - start
    finally:
        process.stop()
    out = process.output
    assert code == 130, out
    assert elapsed < EXIT_BOUND_S, f"took {elapsed:.2f} s to exit"
    assert wait_gone(children, timeout=1.0) == []
    assert "goal in flight is cancelled" in out and "Mission INTERRUPTED" in out
    runner_log = (report / "runner.log").read_text()
    assert "goal cancelled" in runner_log
    assert "Traceback" not in runner_log and "Traceback" not in out  # Ctrl-C reached the group
    assert "Goal 1 canceled" in (report / "sim.log").read_text()
    events = [r["event"] for r in read_jsonl(report / "trace.jsonl") if "event" in r]
    assert events[:3] == ["start", "accepted", "canceled"]
    assert (report / "mission.json").exists()
