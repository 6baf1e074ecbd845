"""Time GridPlanner on the course map: construction and the mission's routes.

Run: ``.venv/bin/python benchmarks/bench_planner.py [--repeats 20]``
"""

from __future__ import annotations

import argparse
import itertools
import math
import os
import statistics
import time

from sar_framework.sim.occupancy import DEFAULT_MAP_PREFIX, load_map
from sar_framework.sim.planner import GridPlanner

BASE = (0.0, 0.0)
ZONES = {"zone_a": (-3.0, 3.0), "zone_b": (3.5, 3.0), "zone_c": (4.0, -3.0), "zone_d": (-3.5, -3.0)}
ROUTES = [
    *((f"base -> {name}", BASE, pose) for name, pose in ZONES.items()),
    *((f"{name} -> base", pose, BASE) for name, pose in ZONES.items()),
    ("zone_a -> zone_c", ZONES["zone_a"], ZONES["zone_c"]),
    ("NW corner -> SE corner", (-5.5, 4.5), (5.5, -4.5)),
    ("NE corner -> SW corner", (5.5, 4.5), (-5.5, -4.5)),
]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=20)
    args = parser.parse_args()

    grid = load_map(DEFAULT_MAP_PREFIX.with_name("final_project_map.yaml"))
    t0 = time.perf_counter()
    planner = GridPlanner(grid, robot_radius=0.22)
    setup_ms = (time.perf_counter() - t0) * 1e3
    print(f"map {grid.width}x{grid.height} cells @ {grid.resolution} m, cpus={os.cpu_count()}")
    print(f"GridPlanner construction: {setup_ms:.1f} ms\n")
    print(f"{'route':<24} {'min ms':>7} {'median':>7} {'max ms':>7} {'wpts':>5} {'length m':>9}")
    for name, start, goal in ROUTES:
        times = []
        for _ in range(args.repeats):
            t0 = time.perf_counter()
            path = planner.plan(start, goal)
            times.append((time.perf_counter() - t0) * 1e3)
        length = sum(math.dist(a, b) for a, b in itertools.pairwise(path))
        print(
            f"{name:<24} {min(times):7.1f} {statistics.median(times):7.1f} {max(times):7.1f}"
            f" {len(path):5d} {length:9.2f}"
        )


if __name__ == "__main__":
    main()
