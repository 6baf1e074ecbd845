"""Soak: several servers stopped in the same instant, N rounds, under CPU load.

    .venv/bin/python benchmarks/soak_server_teardown.py [--rounds 60] [--servers 7] [--burners 2]

What launch does at the end of a mission: SIGINT to every process at once. Each round starts
``--servers`` processes running :func:`sar_framework.ros.serve.serve` with a small node: the
first publishes /clock at 50 Hz, each other one has a service, a publisher and a
subscription on a shared topic and uses the /clock time. It waits until each has
built its node and discovery has had a moment, then sends SIGINT to all of them together.
A round is clean when every process exits 0 within ``--bound-s``; a process still running
then is reported hung (and killed). Meanwhile ``--burners`` busy loops load the cores.

Prints one line per round, then a table: rounds, clean, hung, the teardowns that hung until
:func:`sar_framework.ros.teardown.bounded_teardown` ended their process (exit 0, a line on
stderr), the slowest exit. Exit 0 when every round was clean. Uses a ROS domain leased for the soak.
"""

from __future__ import annotations

import argparse
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from sar_framework.testing.cpu_load import start_burners, stop_burners  # noqa: E402
from sar_framework.testing.ros_env import apply_local_ros_env, lease_domain_id  # noqa: E402

PROBE = """
import sys
from rclpy.node import Node
from rclpy.parameter import Parameter
from rosgraph_msgs.msg import Clock
from std_msgs.msg import String
from std_srvs.srv import Trigger
from sar_framework.ros.serve import serve

def make():
    name, is_clock = sys.argv[1], sys.argv[2] == "clock"
    node = Node(name, parameter_overrides=[Parameter("use_sim_time", value=not is_clock)])
    if not is_clock:
        node.create_service(Trigger, "~/trigger", lambda request, response: response)
        node.create_publisher(String, "teardown_soak", 10)
        node.create_subscription(String, "teardown_soak", lambda message: None, 10)
    else:  # the simulator's part: /clock at 50 Hz
        clock = node.create_publisher(Clock, "/clock", 10)
        now = Clock()

        def tick():
            now.clock.nanosec += 20_000_000
            if now.clock.nanosec >= 1_000_000_000:
                now.clock.sec, now.clock.nanosec = now.clock.sec + 1, 0
            clock.publish(now)

        node.create_timer(0.02, tick)
    print("ready", flush=True)
    return node

serve(make, sys.argv[1], sys.argv[:1])
"""
#: Wall seconds between the last server's "ready" and the SIGINT: discovery done, all matched.
SETTLE_S = 4.0


def one_round(servers: int, bound_s: float) -> tuple[int, int, float]:
    """Start ``servers`` probes, stop them together.

    Returns:
        How many hung or failed, how many teardowns were cut short at their bound (their
        line on stderr), the slowest exit in seconds.
    """
    with tempfile.TemporaryFile("w+") as errors:
        procs = [subprocess.Popen([sys.executable, "-c", PROBE, f"teardown_probe_{index}",
                                   "clock" if index == 0 else "server"],
                                  stdout=subprocess.PIPE, stderr=errors, text=True)
                 for index in range(servers)]
        for proc in procs:
            assert proc.stdout is not None
            proc.stdout.readline()  # "ready", or "" when it died: the exit code says so
        time.sleep(SETTLE_S)
        sent = time.monotonic()
        for proc in procs:
            proc.send_signal(signal.SIGINT)
        hung = 0
        for proc in procs:
            try:
                proc.wait(timeout=max(0.1, bound_s - (time.monotonic() - sent)))
            except subprocess.TimeoutExpired:
                hung += 1
                proc.kill()
                proc.wait()
            else:
                hung += proc.returncode != 0
        slowest = time.monotonic() - sent
        errors.seek(0)
        return hung, errors.read().count("teardown still running after"), slowest


def main() -> int:
    """Run the soak; print each round and the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=60)
    parser.add_argument("--servers", type=int, default=7)
    parser.add_argument("--burners", type=int, default=2)
    parser.add_argument("--bound-s", type=float, default=30.0,
                        help="wall seconds after the SIGINT before a server counts as hung")
    args = parser.parse_args()
    lease = lease_domain_id()
    apply_local_ros_env(lease.domain_id)
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(1))  # the burners stop too
    burners = start_burners(args.burners, 3600.0)
    rounds = []
    try:
        for index in range(args.rounds):
            hung, cut_short, slowest = one_round(args.servers, args.bound_s)
            rounds.append((hung, cut_short, slowest))
            print(f"round {index + 1}: {'clean' if not hung else f'{hung} hung or failed'}, "
                  f"{cut_short} cut short, slowest exit {slowest:.1f} s", flush=True)
    finally:
        stop_burners(burners)
        lease.release()
    clean = sum(1 for hung, _, _ in rounds if not hung)
    print("\n| rounds | clean | hung or failed servers | teardowns cut short | slowest exit |")
    print("| --- | --- | --- | --- | --- |")
    print(f"| {len(rounds)} | {clean} | {sum(r[0] for r in rounds)} | "
          f"{sum(r[1] for r in rounds)} | {max(r[2] for r in rounds):.1f} s |")
    return 0 if clean == len(rounds) else 1


if __name__ == "__main__":
    sys.exit(main())
