"""Benchmark: how long ``make run`` takes to start, tick and stop, phase by phase.

    .venv/bin/python benchmarks/bench_startup.py [--runs 5] [--direct]

Each run is the README's ``make run`` (the set-up check, then ``sar-tree run`` of the
reference mission in the embedded simulator), on a ROS domain leased for the benchmark;
``--direct`` runs ``sar-tree run`` alone (no ``make``, no set-up check) into a temporary
folder. The phases come from what the run records, in wall seconds since ``sar-tree run``
started (:mod:`sar_framework.run_clock`), never from log text:

- ``processes up``: the runner sees the simulator's Nav2 services (every process started,
  imported, discovered): ``status.json`` ``startup.nav2_discovered_s``;
- ``Nav2 active``: amcl and bt_navigator answered ACTIVE: ``startup.nav2_active_s``;
- ``AMCL seeded``: BasicNavigator's seed and ``waitUntilNav2Active`` done:
  ``startup.amcl_seeded_s``;
- ``first tick``: ``status.json`` ``wall_first_tick_s``;
- ``last tick``: the runner's ``completion`` event in ``events.jsonl``;
- ``all stopped``: every child stopped, the verdict written: the ``verdict`` event;
- ``sar-tree run`` / ``make run``: the command's whole wall time, report included, on the
  benchmark's clock (``make run`` with its set-up check).

Targets on an idle machine: first tick <= 6 s, ``make run`` <= 12 s. One table: median and
worst of the runs; the machine's load average is printed before and after.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from sar_framework.events.event import kind_name  # noqa: E402
from sar_framework.events.jsonl import read_events  # noqa: E402
from sar_framework.testing.ros_env import apply_local_ros_env, lease_domain_id  # noqa: E402

TREE = "trees/search_and_rescue.yaml"
MAKE_REPORT = REPO / "reports" / "latest"
#: Row label -> where its figure is (``startup.KEY``, ``status.KEY``, ``event.KIND``,
#: ``total``).
PHASES = (
    ("processes up", "startup.nav2_discovered_s"),
    ("Nav2 active", "startup.nav2_active_s"),
    ("AMCL seeded", "startup.amcl_seeded_s"),
    ("first tick", "status.wall_first_tick_s"),
    ("last tick", "event.completion"),
    ("all stopped", "event.verdict"),
)
TARGETS = {"first tick": 6.0, "make run": 12.0}


def run_once(direct: bool, folder: Path, index: int) -> dict[str, float]:
    """One run; return its figures (seconds), by row label."""
    if direct:
        report = folder / f"run_{index}"
        argv = [str(REPO / ".venv" / "bin" / "sar-tree"), "run", TREE, "--report-dir",
                str(report)]
        label = "sar-tree run"
    else:
        report = MAKE_REPORT
        argv = ["make", "-s", "run"]
        label = "make run"
    started = time.monotonic()
    done = subprocess.run(argv, cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          text=True, timeout=600, check=False)
    total = time.monotonic() - started
    if done.returncode != 0:
        raise SystemExit(f"run {index}: {' '.join(argv)} exited {done.returncode}:\n"
                         f"{done.stdout[-2000:]}")
    return {**phases(report), label: total}


def phases(report: Path) -> dict[str, float]:
    """The phases' wall seconds read from a run's ``status.json`` and ``events.jsonl``."""
    status: dict[str, Any] = json.loads((report / "status.json").read_text())
    events = {kind_name(e.kind): e.wall_s for e in read_events(report / "events.jsonl")}
    figures: dict[str, float] = {}
    for label, where in PHASES:
        source, _, key = where.partition(".")
        value = {"startup": status.get("startup", {}), "status": status,
                 "event": events}[source].get(key)
        if value is None:
            raise SystemExit(f"{report}: no {where} recorded")
        figures[label] = float(value)
    return figures


def table(rows: list[dict[str, float]]) -> str:
    """The median and worst of every figure, one line each."""
    lines = [f"{'phase (s since start)':<24}{'median':>8}{'worst':>8}{'target':>8}"]
    for label in rows[0]:
        values = [row[label] for row in rows]
        target = TARGETS.get(label)
        lines.append(f"{label:<24}{statistics.median(values):>8.2f}{max(values):>8.2f}"
                     f"{f'<= {target:g}' if target else '':>8}")
    return "\n".join(lines)


def load() -> str:
    """The load averages (1, 5, 15 min) as text."""
    return " ".join(f"{value:.2f}" for value in os.getloadavg())


def main(argv: list[str] | None = None) -> int:
    """Run the mission ``--runs`` times; print the phase table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--direct", action="store_true",
                        help="run sar-tree run alone, not make run")
    args = parser.parse_args(argv)
    lease = lease_domain_id()
    apply_local_ros_env(lease.domain_id)
    print(f"{'sar-tree run' if args.direct else 'make run'} x{args.runs}, {TREE}, "
          f"{os.cpu_count()} CPUs, ROS_DOMAIN_ID={lease.domain_id}, load before: {load()}",
          flush=True)
    try:
        with tempfile.TemporaryDirectory(prefix="bench_startup_") as tmp:
            rows = [run_once(args.direct, Path(tmp), i) for i in range(args.runs)]
    finally:
        lease.release()
    print(table(rows))
    print(f"load after: {load()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
