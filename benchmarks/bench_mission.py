"""Benchmark: the whole default mission through ``sar-tree run`` at several speed factors.

    .venv/bin/python benchmarks/bench_mission.py [--speeds 5,10,20,40,80,160] [--interrupts 3]

For each speed the reference mission (trees/search_and_rescue.yaml) runs once as a real
``sar-tree run`` process (simulator, both servers, runner: four processes over DDS). Columns:

- ``total``: wall seconds from starting ``sar-tree run`` until it exited (set-up, mission,
  orderly stop, report);
- ``1st tick``: wall seconds from start until the first tick (the first goal's log line);
- ``mission``: wall seconds from the first tick to the mission's completion (runner);
- ``sim``: simulated seconds of the mission; ``RTF``: sim / mission (achieved speed);
- ``ticks/s``: ticks per wall second while ticking (2 Hz of simulated time x speed);
- ``ok``: the spec's outcome (4 zones in order, 2 acknowledged survivors, one base goal).

Then Ctrl-C-to-exit: SIGINT while the first goal is in flight; wall seconds until
``sar-tree run`` and all its children have exited (the goal is cancelled first).
Uses ``ROS_DOMAIN_ID`` from the environment (default 43) and loopback-only discovery.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parents[1]
TREE = REPO / "trees" / "search_and_rescue.yaml"
_FIRST_GOAL = re.compile(r"^\[\s*([0-9.]+)s\] runner \| --- Zone 1/")


def _env() -> dict[str, str]:
    env = dict(os.environ)
    env.setdefault("ROS_DOMAIN_ID", "43")
    env["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
    return env


def _start(args: list[str], report: Path) -> subprocess.Popen[str]:
    return subprocess.Popen(
        [sys.executable, "-m", "sar_framework", "run", str(TREE), "--report-dir", str(report),
         *args], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=_env(),
        cwd=REPO, start_new_session=True)


def run_once(speed: float, folder: Path) -> dict[str, Any]:
    """Run the default mission at ``speed``; return the row's numbers."""
    report = folder / f"speed_{speed:g}"
    start = time.monotonic()
    proc = _start(["--speed", f"{speed:g}", "--timeout", "600"], report)
    out, _ = proc.communicate(timeout=900)
    total = time.monotonic() - start
    first = next((float(m.group(1)) for line in out.splitlines()
                  if (m := _FIRST_GOAL.match(line))), float("nan"))
    mission = json.loads((report / "mission.json").read_text())
    goals = [r for r in (report / "trace.jsonl").read_text().splitlines() if '"accepted"' in r]
    ok = (proc.returncode == 0
          and [z["id"] for z in mission["zones_visited"]] == ["zone_a", "zone_b", "zone_c",
                                                             "zone_d"]
          and sum(1 for s in mission["survivors"] if s["acknowledged"]) == 2
          and len(goals) == 5)
    ticking = mission["runner_wall_duration_s"] - mission["wall_first_tick_s"]
    return {"speed": speed, "total": total, "first_tick": first, "mission": ticking,
            "sim": mission["sim_duration_s"], "rtf": mission["real_time_factor"],
            "tps": mission["ticks_per_wall_s"], "ok": ok, "code": proc.returncode}


def interrupt_once(folder: Path, index: int) -> float:
    """SIGINT ``sar-tree run`` while the first goal is in flight; return the exit time."""
    report = folder / f"interrupt_{index}"
    proc = _start(["--speed", "5"], report)
    assert proc.stdout is not None
    for line in proc.stdout:
        if _FIRST_GOAL.match(line):
            break
    time.sleep(0.5)
    start = time.monotonic()
    os.killpg(proc.pid, signal.SIGINT)
    proc.communicate(timeout=30)
    elapsed = time.monotonic() - start
    cancelled = "goal cancelled" in (report / "runner.log").read_text()
    if not cancelled:
        print(f"  warning: interrupt run {index}: no cancel in runner.log", file=sys.stderr)
    return elapsed


def main(argv: list[str] | None = None) -> int:
    """Print the speed table and the Ctrl-C-to-exit figures."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--speeds", default="5,10,20,40,80,160")
    parser.add_argument("--interrupts", type=int, default=3)
    args = parser.parse_args(argv)
    speeds = [float(s) for s in args.speeds.split(",") if s]
    with tempfile.TemporaryDirectory(prefix="bench_mission_") as tmp:
        folder = Path(tmp)
        print(f"default mission via sar-tree run ({os.cpu_count()} CPUs)")
        print(f"{'speed':>6} {'total s':>8} {'1st tick s':>10} {'mission s':>9} {'sim s':>7} "
              f"{'RTF':>6} {'ticks/s':>8} {'ok':>4}")
        for speed in speeds:
            r = run_once(speed, folder)
            print(f"{r['speed']:>6g} {r['total']:>8.2f} {r['first_tick']:>10.2f} "
                  f"{r['mission']:>9.2f} {r['sim']:>7.1f} {r['rtf'] or 0:>6.1f} "
                  f"{r['tps'] or 0:>8.1f} {'yes' if r['ok'] else 'NO':>4}", flush=True)
        if args.interrupts:
            times = [interrupt_once(folder, i) for i in range(args.interrupts)]
            print(f"Ctrl-C to exit (goal in flight, {len(times)} runs): "
                  f"median {statistics.median(times):.2f} s, max {max(times):.2f} s "
                  f"(target <= 2 s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
