"""Every benchmark script starts: its imports resolve and ``--help`` exits 0.

The benchmarks are not run by ``make test`` (they measure; ``make bench`` runs them), so a
renamed function they import would otherwise go unnoticed until someone measures.
"""

from __future__ import annotations

import importlib.util
import json
import subprocess
import sys
from pathlib import Path

import pytest

BENCHMARKS = sorted((Path(__file__).resolve().parents[2] / "benchmarks").glob("*.py"))


def test_there_are_benchmarks() -> None:
    assert len(BENCHMARKS) >= 10, BENCHMARKS


@pytest.mark.parametrize("script", BENCHMARKS, ids=[p.stem for p in BENCHMARKS])
def test_the_benchmark_starts(script: Path) -> None:
    done = subprocess.run([sys.executable, str(script), "--help"], capture_output=True,
                          text=True, timeout=60, check=False)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "usage:" in done.stdout, done.stdout


def test_bench_startup_reads_the_phases_of_a_run_whose_app_has_events_of_its_own(
        tmp_path: Path) -> None:
    # An app's event kinds are plain names, not the core's EventKind: the benchmark read
    # ``kind.value`` of every event and stopped at the search-and-rescue app's first one.
    spec = importlib.util.spec_from_file_location("bench_startup_under_test",
                                                  BENCHMARKS[0].parent / "bench_startup.py")
    assert spec and spec.loader
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    (tmp_path / "status.json").write_text(json.dumps({
        "startup": {"nav2_discovered_s": 1.2, "nav2_active_s": 1.3, "amcl_seeded_s": 5.5},
        "wall_first_tick_s": 5.6}))
    fields = {"node_name": "", "node_uid": "", "node_kind": "", "status": "", "message": "",
              "position": None, "fields": {}}
    events = [("started", 5.6), ("survivor_reported", 8.0), ("completion", 10.8),
              ("verdict", 11.2)]
    (tmp_path / "events.jsonl").write_text("".join(
        json.dumps({"kind": kind, "seq": seq, "sim_s": wall * 20, "wall_s": wall, **fields})
        + "\n" for seq, (kind, wall) in enumerate(events, 1)))
    assert bench.phases(tmp_path) == {
        "processes up": 1.2, "Nav2 active": 1.3, "AMCL seeded": 5.5, "first tick": 5.6,
        "last tick": 10.8, "all stopped": 11.2}
