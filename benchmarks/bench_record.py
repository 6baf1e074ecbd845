"""Benchmark: what ``sar-tree run --record`` costs the reference mission.

    .venv/bin/python benchmarks/bench_record.py [--pairs 3] [--speeds 20,160]

Paired runs of the reference mission (trees/search_and_rescue.yaml) through ``sar-tree
run``, one without and one with ``--record FILE.mcap``, alternating which goes first.
Columns per run:

- ``mission s``: wall seconds from the first tick to the mission's completion (runner);
- ``RTF``: simulated seconds per wall second while ticking;
- ``CPU s``: user + system CPU seconds of ``sar-tree run`` and all its children;
- ``MB``: size of the recording.

Speed 20 is the default (the simulator paces the mission, so a slowdown shows only if
the recorder starves it); speed 160 asks for more than two cores give, so every CPU
second the recorder takes shows as mission time. The verdict compares median mission
times (goal: recording at most 10 % slower). Uses ``ROS_DOMAIN_ID`` from the
environment (default 43) and loopback-only discovery.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parents[1]
TREE = REPO / "trees" / "search_and_rescue.yaml"
GOAL_OVERHEAD = 0.10


def _env() -> dict[str, str]:
    env = dict(os.environ)
    env.setdefault("ROS_DOMAIN_ID", "43")
    env["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
    return env


def _children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run_once(speed: float, folder: Path, record: bool, index: int) -> dict[str, Any]:
    """Run the mission once; return its numbers."""
    name = f"speed{speed:g}_{index}_{'rec' if record else 'plain'}"
    report, bag = folder / name, folder / f"{name}.mcap"
    args = [sys.executable, "-m", "sar_framework", "run", str(TREE), "--report-dir",
            str(report), "--speed", f"{speed:g}", "--timeout", "600"]
    cpu_before = _children_cpu()
    proc = subprocess.run([*args, *(["--record", str(bag)] if record else [])],
                          capture_output=True, text=True, env=_env(), cwd=REPO, check=False,
                          timeout=900)
    cpu = _children_cpu() - cpu_before
    mission = json.loads((report / "mission.json").read_text())
    ticking = mission["runner_wall_duration_s"] - mission["wall_first_tick_s"]
    ok = proc.returncode == 0 and len(mission["zones_visited"]) == 4 and \
        (not record or bag.stat().st_size > 0)
    return {"mission": ticking, "rtf": mission["real_time_factor"] or 0.0, "cpu": cpu,
            "mb": bag.stat().st_size / 1e6 if record else 0.0, "ok": ok}


def main(argv: list[str] | None = None) -> int:
    """Print one table per speed and the verdict."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, default=3)
    parser.add_argument("--speeds", default="20,160")
    args = parser.parse_args(argv)
    verdicts = []
    with tempfile.TemporaryDirectory(prefix="bench_record_") as tmp:
        folder = Path(tmp)
        print(f"reference mission via sar-tree run, with and without --record "
              f"({os.cpu_count()} CPUs, {args.pairs} pairs per speed)")
        for speed in (float(s) for s in args.speeds.split(",") if s):
            print(f"\nspeed {speed:g}")
            print(f"{'pair':>4} {'record':>7} {'mission s':>9} {'RTF':>6} {'CPU s':>6} "
                  f"{'MB':>5} {'ok':>4}")
            times: dict[bool, list[float]] = {False: [], True: []}
            for pair in range(args.pairs):
                order = (False, True) if pair % 2 == 0 else (True, False)
                for record in order:
                    r = run_once(speed, folder, record, pair)
                    times[record].append(r["mission"])
                    print(f"{pair + 1:>4} {'yes' if record else 'no':>7} {r['mission']:>9.2f} "
                          f"{r['rtf']:>6.1f} {r['cpu']:>6.2f} {r['mb']:>5.2f} "
                          f"{'yes' if r['ok'] else 'NO':>4}", flush=True)
            plain, recorded = statistics.median(times[False]), statistics.median(times[True])
            overhead = recorded / plain - 1.0
            verdicts.append(overhead <= GOAL_OVERHEAD)
            print(f"median mission: {plain:.2f} s without, {recorded:.2f} s with --record: "
                  f"{overhead:+.1%} (goal <= {GOAL_OVERHEAD:.0%}: "
                  f"{'met' if overhead <= GOAL_OVERHEAD else 'NOT met'})")
    return 0 if all(verdicts) else 1


if __name__ == "__main__":
    sys.exit(main())
