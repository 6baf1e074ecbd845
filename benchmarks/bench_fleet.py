"""Benchmark: the fleet mission with 1 to 4 robots, and a lost robot's zones re-awarded.

    .venv/bin/python benchmarks/bench_fleet.py [--robots 1,2,3,4] [--speed 20] [--no-loss]

Each row runs ``sar-tree run trees/fleet_search.yaml --robots N`` as a real process (one
simulator, the base, the zone coordinator, a detect server and a runner per robot, over
DDS on loopback) at ``--speed`` (default: the simulator's default speed). Columns:

- ``mission (sim)``: simulated seconds from the first robot's first tick to the last
  robot's end (each robot's ``status.json``: ``sim_start_s``, ``sim_end_s``);
- ``speed-up``: the 1-robot mission time over this one;
- ``wall``: wall seconds of the whole ``sar-tree run`` (set-up, mission, stop, reports);
- ``zones``: who searched which zone (the coordinator's ``searched`` events);
- ``ok``: the fleet's verdict (every zone searched once, every robot home).

Then a lost robot (unless ``--no-loss``): 3 robots at ``--loss-speed`` (default 1x);
``robot2``'s runner is SIGKILLed as soon as its first award shows in the coordinator's
events file, which is followed as it grows; the table gives the wall seconds from the kill
to its ``robot_lost`` line and to the ``award`` of the reopened zone to another robot (the
coordinator's ``robot_timeout_wall_s``, 3 s by default, less the heartbeat's phase, plus
the next round's bids), and what became of the zone. The killed robot's Nav2 stack lives on
in the simulator and finishes the goal it was given: once its body stands on the zone, the
next robot searches from NavFn's approach point beside it (docs/how-to/fleet.md).
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))
TREE = "trees/fleet_search.yaml"

from sar_framework.events.jsonl import read_json_lines  # noqa: E402
from sar_framework.sim.params import SPEED  # noqa: E402 - after the path is set


def _env() -> dict[str, str]:
    env = dict(os.environ)
    env.setdefault("ROS_DOMAIN_ID", "43")
    env["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
    return env


def _start(robots: int, speed: float, report: Path) -> subprocess.Popen[str]:
    return subprocess.Popen(
        [sys.executable, "-m", "sar_framework", "run", TREE, "--robots", str(robots),
         "--speed", f"{speed:g}", "--timeout", "600", "--report-dir", str(report)],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, text=True, env=_env(),
        cwd=REPO, start_new_session=True)


def _json(path: Path) -> dict[str, Any]:
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}


def run_fleet(robots: int, speed: float, folder: Path) -> dict[str, Any]:
    """One fleet mission; the row's numbers."""
    report = folder / f"robots_{robots}"
    start = time.monotonic()
    proc = _start(robots, speed, report)
    code = proc.wait(timeout=900)
    wall = time.monotonic() - start
    fleet = _json(report / "fleet.json")
    statuses = [_json(report / name / "status.json") for name in fleet.get("robots", {})]
    starts = [s["sim_start_s"] for s in statuses if isinstance(s.get("sim_start_s"), float)]
    ends = [s["sim_end_s"] for s in statuses if isinstance(s.get("sim_end_s"), float)]
    zones = {zone: ",".join(z["searched_by"]) for zone, z in fleet.get("zones", {}).items()}
    return {"robots": robots, "code": code, "wall": wall, "outcome": fleet.get("outcome"),
            "sim": max(ends) - min(starts) if starts and ends else None, "zones": zones}


def lost_robot(speed: float, folder: Path) -> dict[str, Any]:
    """3 robots, robot2's runner killed after its first award: the coordinator's delays."""
    report = folder / "lost"
    events_path = report / "fleet_events.jsonl"
    proc = _start(3, speed, report)
    seen: dict[int, float] = {}  # event seq -> when it showed up (monotonic)
    killed_at: float | None = None
    claimed = ""
    result: dict[str, Any] = {"lost_s": None, "reawarded_s": None, "zone": ""}
    deadline = time.monotonic() + 600
    while proc.poll() is None and time.monotonic() < deadline:
        now = time.monotonic()
        for event in read_json_lines(events_path):
            seen.setdefault(int(event.get("seq", 0)), now)
            kind, robot = event.get("kind"), event.get("robot")
            if killed_at is None and kind == "award" and robot == "robot2":
                claimed = str(event.get("zone_id"))
                pids = subprocess.run(
                    ["pgrep", "-f", f"status_file:={report / 'robot2' / 'status.json'}"],
                    capture_output=True, text=True, check=False).stdout.split()
                for pid in pids:
                    os.kill(int(pid), signal.SIGKILL)
                killed_at = time.monotonic()
                result["zone"] = claimed
            if killed_at is not None and seen[int(event.get("seq", 0))] >= killed_at:
                if kind == "robot_lost" and robot == "robot2" and result["lost_s"] is None:
                    result["lost_s"] = seen[int(event["seq"])] - killed_at
                if kind == "award" and event.get("zone_id") == claimed and robot != "robot2" \
                        and result["reawarded_s"] is None:
                    result["reawarded_s"] = seen[int(event["seq"])] - killed_at
        time.sleep(0.02)
    proc.wait(timeout=120)
    fleet = _json(report / "fleet.json")
    result["searched"] = {zone: ",".join(z["searched_by"])
                          for zone, z in fleet.get("zones", {}).items()}
    result["fate"] = [f"{e.get('kind')}({e.get('robot') or ''})"
                      for e in read_json_lines(events_path)
                      if claimed and (e.get("zone_id") == claimed
                                      or claimed in (e.get("zone_ids") or []))
                      and e.get("kind") != "bid"]
    return result


def main() -> int:
    """Run the rows and print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robots", default="1,2,3,4")
    parser.add_argument("--speed", type=float, default=SPEED.default)
    parser.add_argument("--no-loss", action="store_true")
    parser.add_argument("--loss-speed", type=float, default=1.0, metavar="X",
                        help="the lost-robot run's speed (default 1: the killed robot's body, "
                        "whose Nav2 drives on, is still on its way when its zone is "
                        "re-awarded; the coordinator's bounds are wall time)")
    parser.add_argument("--keep", type=Path, metavar="DIR",
                        help="keep the runs' folders in DIR (default: a temporary folder)")
    args = parser.parse_args()
    rows = []
    with tempfile.TemporaryDirectory(prefix="sar_bench_fleet_") as tmp:
        folder = args.keep or Path(tmp)
        for robots in (int(n) for n in args.robots.split(",") if n.strip()):
            rows.append(run_fleet(robots, args.speed, folder))
            row = rows[-1]
            print(f"  {robots} robot(s): {row['outcome']} in {row['wall']:.1f} s wall",
                  file=sys.stderr)
        lost = None if args.no_loss else lost_robot(args.loss_speed, folder)
    base = next((r["sim"] for r in rows if r["robots"] == 1 and r["sim"]), None)
    print(f"fleet_search.yaml at {args.speed:g}x ({os.cpu_count()} cores)")
    print(f"{'robots':>6} {'mission (sim)':>14} {'speed-up':>9} {'wall':>7}  ok       zones")
    for row in rows:
        sim = f"{row['sim']:.1f} s" if row["sim"] is not None else "-"
        gain = f"{base / row['sim']:.2f}x" if base and row["sim"] else "-"
        zones = " ".join(f"{z}:{by}" for z, by in sorted(row["zones"].items()))
        print(f"{row['robots']:>6} {sim:>14} {gain:>9} {row['wall']:>6.1f}s  "
              f"{row['outcome'] or '-':<8} {zones}")
    if lost is not None:
        def fmt(value: float | None) -> str:
            return f"{value:.2f} s" if value is not None else "not seen"

        print(f"lost robot at {args.loss_speed:g}x (robot2 SIGKILLed as it won "
              f"{lost['zone'] or '-'}): robot_lost, its zone back to auction, after "
              f"{fmt(lost['lost_s'])}; re-awarded after {fmt(lost['reawarded_s'])}, once a "
              "robot asked for work (wall); searched: "
              + " ".join(f"{z}:{by}" for z, by in sorted(lost["searched"].items())))
        print(f"  {lost['zone'] or 'its zone'} in the coordinator's events: "
              + " ".join(lost["fate"]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
