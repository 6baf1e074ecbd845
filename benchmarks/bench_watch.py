"""Benchmark: how often ``sar-tree watch`` redraws the reference mission, and how late.

    .venv/bin/python benchmarks/bench_watch.py [--runs 3] [--speed 20] [--fps 20]

Each run starts ``sar-tree watch`` in a pseudo-terminal (a real rich ``Live`` display,
output read and discarded), then the reference mission (trees/search_and_rescue.yaml)
through ``sar-tree run``. Columns per run:

- ``ticks``: ticks the runner made; ``seen``: status messages the watcher received;
- ``ticks/s``: the runner's rate while ticking (2 Hz of simulated time x speed);
- ``frames/s``: frames the watcher drew per second from its first tick to the mission's
  end (capped by ``--fps``); ``frames``: their number;
- ``exit s``: when the watcher exited, in wall seconds after ``sar-tree run`` did
  (negative: before; it leaves by itself as soon as the mission is over).

Uses ``ROS_DOMAIN_ID`` from the environment (default 43) and loopback-only discovery.
"""

from __future__ import annotations

import argparse
import json
import os
import pty
import re
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
TREE = REPO / "trees" / "search_and_rescue.yaml"
_ANSI = re.compile(r"\x1b\[[0-9;?]*[A-Za-z]")
_SUMMARY = re.compile(r"(\d+) ticks seen, (\d+) frames drawn \(([0-9.]+) frames/s\)")


def _env() -> dict[str, str]:
    env = dict(os.environ)
    env.setdefault("ROS_DOMAIN_ID", "43")
    env["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
    env["COLUMNS"], env["LINES"] = "120", "40"
    return env


def _drain(fd: int, sink: list[bytes]) -> None:
    while True:
        try:
            chunk = os.read(fd, 65536)
        except OSError:
            return
        if not chunk:
            return
        sink.append(chunk)


def run_once(folder: Path, index: int, speed: float, fps: float) -> dict[str, float]:
    """One mission with a watcher on a pseudo-terminal; return the row's numbers."""
    primary, secondary = pty.openpty()
    watcher = subprocess.Popen(
        [sys.executable, "-m", "sar_framework", "watch", "--wait", "120", "--fps", f"{fps:g}"],
        stdin=secondary, stdout=secondary, stderr=secondary, env=_env(), cwd=REPO)
    os.close(secondary)
    screen: list[bytes] = []
    reader = threading.Thread(target=_drain, args=(primary, screen), daemon=True)
    reader.start()
    ended: list[float] = []
    waiter = threading.Thread(target=lambda: (watcher.wait(), ended.append(time.monotonic())),
                              daemon=True)
    waiter.start()
    report = folder / f"run_{index}"
    subprocess.run([sys.executable, "-m", "sar_framework", "run", str(TREE), "--speed",
                    f"{speed:g}", "--report-dir", str(report)], capture_output=True,
                   env=_env(), cwd=REPO, check=False, timeout=600)
    run_ended = time.monotonic()
    waiter.join(timeout=60)
    exit_s = (ended[0] if ended else time.monotonic()) - run_ended
    reader.join(timeout=5)
    os.close(primary)
    text = _ANSI.sub("", b"".join(screen).decode(errors="replace"))
    match = _SUMMARY.search(text)
    mission = json.loads((report / "mission.json").read_text())
    return {"ticks": mission["ticks"], "tps": mission["ticks_per_wall_s"] or 0.0,
            "seen": int(match.group(1)) if match else 0,
            "frames": int(match.group(2)) if match else 0,
            "fps": float(match.group(3)) if match else 0.0, "exit": exit_s,
            "code": watcher.returncode}


def main(argv: list[str] | None = None) -> int:
    """Print the table and the medians."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--speed", type=float, default=20.0)
    parser.add_argument("--fps", type=float, default=20.0)
    args = parser.parse_args(argv)
    rows = []
    with tempfile.TemporaryDirectory(prefix="bench_watch_") as tmp:
        print(f"sar-tree watch on the reference mission at speed {args.speed:g}, "
              f"--fps {args.fps:g} ({os.cpu_count()} CPUs)")
        print(f"{'run':>3} {'ticks':>6} {'seen':>5} {'ticks/s':>8} {'frames':>7} "
              f"{'frames/s':>9} {'exit s':>7} {'rc':>3}")
        for index in range(args.runs):
            r = run_once(Path(tmp), index, args.speed, args.fps)
            rows.append(r)
            print(f"{index + 1:>3} {r['ticks']:>6} {r['seen']:>5} {r['tps']:>8.1f} "
                  f"{r['frames']:>7} {r['fps']:>9.1f} {r['exit']:>7.2f} {r['code']:>3}",
                  flush=True)
    print(f"median: {statistics.median(r['fps'] for r in rows):.1f} frames/s for "
          f"{statistics.median(r['tps'] for r in rows):.1f} ticks/s; the watcher exited "
          f"{statistics.median(r['exit'] for r in rows):+.2f} s relative to sar-tree run")
    return 0 if all(r["code"] == 0 and r["frames"] > 0 for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
