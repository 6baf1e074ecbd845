"""Ctrl-C mid-mission: the goal in flight is cancelled and every process ends.

How quickly is a figure of benchmarks/bench_mission.py ("Ctrl-C to exit"), not checked here.
"""

from __future__ import annotations

import signal
import time

import pytest

from .helpers import DEFAULT_TREE, child_pids, read_jsonl, sar_tree_run, wait_gone

pytestmark = [pytest.mark.slow, pytest.mark.ros]



def test_sigint_mid_navigation_cancels_the_goal_and_exits_130(tmp_path) -> None:
    report = tmp_path / "report"
    process = sar_tree_run([str(DEFAULT_TREE), "--speed", "2"], report)
    try:
        process.wait_for_output(r"--- Zone 1/4: zone_a", timeout=60)
        children = child_pids(process.pid)
        assert len(children) == 4
        # The goal in flight: the simulator's trace says it was accepted.
        trace = report / "trace.jsonl"
        deadline = time.monotonic() + 60  # outer safety bound (about 1 s expected)
        while '"accepted"' not in (trace.read_text() if trace.exists() else ""):
            assert time.monotonic() < deadline, process.output  # outer safety bound
            time.sleep(0.1)
        process.send_signal(signal.SIGINT)
        code = process.wait(timeout=60)  # outer safety bound (about 1 s expected)
    finally:
        process.stop()
    out = process.output
    assert code == 130, out
    assert wait_gone(children) == []
    assert "goal in flight is cancelled" in out and "Mission INTERRUPTED" in out
    runner_log = (report / "runner.log").read_text()
    assert "goal cancelled" in runner_log
    assert "Traceback" not in runner_log and "Traceback" not in out  # Ctrl-C reached the group
    assert "Goal 1 canceled" in (report / "sim.log").read_text()
    events = [r["event"] for r in read_jsonl(report / "trace.jsonl") if "event" in r]
    assert events[:3] == ["start", "accepted", "canceled"]
    assert (report / "mission.json").exists()
