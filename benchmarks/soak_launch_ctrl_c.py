"""Soak: Ctrl-C in the middle of the mission under ``ros2 launch``, N times, under CPU load.

    .venv/bin/python benchmarks/soak_launch_ctrl_c.py [--runs 20] [--burners 2]

Each run is the real-stack test's scenario (``tests/sar_testing/launch_ctrl_c.py``):
``ros2 launch sar_framework search_and_rescue.launch.py nav2:=embedded speed:=1.0``, wait for
the first zone, ``ros2 node list``, SIGINT to the launch's process group. A run is clean
when launch exits 0, nothing prints a traceback and every process (simulator, both servers,
runner) reports "process has finished cleanly". Meanwhile ``--burners`` busy-loop processes
(default: one per core) load the machine; each ends by itself after ``--burn-bound-s`` and
all are stopped when the soak ends. Prints one line per run, then a table: runs, clean, and
each failure with its process. Exit 0 when every run was clean. Needs the real ROS 2 stack
in the venv (``make setup``); uses a ROS domain leased for the soak.
"""

from __future__ import annotations

import argparse
import collections
import os
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "tests"))

from sar_testing.launch_ctrl_c import ROS2, ctrl_c_mid_mission  # noqa: E402

from sar_framework.testing.cpu_load import start_burners, stop_burners  # noqa: E402
from sar_framework.testing.ros_env import apply_local_ros_env, lease_domain_id  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    """Run the soak; return 0 when every run was clean."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=20, help="repetitions (default 20)")
    parser.add_argument("--burners", type=int, default=os.cpu_count() or 2,
                        help="busy-loop processes loading the cores (default: one per core)")
    parser.add_argument("--burn-bound-s", type=float, default=3600.0,
                        help="longest a burner runs if the soak cannot stop it")
    parser.add_argument("--log-dir", type=Path, default=None,
                        help="where a failed run's launch output is kept (default: a new "
                        "temporary folder, named in the table)")
    args = parser.parse_args(argv)
    if not ROS2.exists():
        print(f"soak: {ROS2} is missing: build the ROS 2 stack with make setup",
              file=sys.stderr)
        return 2
    log_dir = args.log_dir or Path(tempfile.mkdtemp(prefix="sar_soak_logs_"))
    log_dir.mkdir(parents=True, exist_ok=True)
    lease = lease_domain_id()
    apply_local_ros_env(lease.domain_id)
    burners = start_burners(args.burners, args.burn_bound_s)
    started = time.monotonic()
    clean = 0
    failures: collections.Counter[str] = collections.Counter()
    try:
        for index in range(1, args.runs + 1):
            begun = time.monotonic()
            with tempfile.TemporaryDirectory(prefix="sar_soak_") as folder:
                run = ctrl_c_mid_mission(Path(folder))
            found = run.failures()
            if found:
                (log_dir / f"run_{index:03}.log").write_text(run.output, encoding="utf-8")
            clean += not found
            failures.update(line.splitlines()[0] for line in found)
            verdict = "clean" if not found else "; ".join(f.splitlines()[0] for f in found)
            print(f"run {index:>3}/{args.runs}  {time.monotonic() - begun:5.1f} s  {verdict}",
                  flush=True)
    finally:
        stop_burners(burners)
        lease.release()
    print(f"\nCtrl-C under ros2 launch, {args.burners} CPU burner(s), "
          f"ROS_DOMAIN_ID={lease.domain_id}, {time.monotonic() - started:.0f} s in all")
    print(f"{'runs':<8}{args.runs:>4}")
    print(f"{'clean':<8}{clean:>4}")
    for line, count in sorted(failures.items()):
        print(f"{'failed':<8}{count:>4}  {line}")
    if failures:
        print(f"launch output of each failed run: {log_dir}/run_NNN.log")
    return 0 if clean == args.runs else 1


if __name__ == "__main__":
    sys.exit(main())
