"""A server whose teardown hangs says where; one that spins past its bound lets DDS through."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytestmark = pytest.mark.ros

# destroy_node "hangs" until the test has seen the stacks (the release file), so the order is
# made, not hoped for: the report comes while the teardown still runs, whatever the load.
SLOW_TEARDOWN = """
import sys, time
from pathlib import Path
from rclpy.node import Node
from sar_framework.ros.serve import serve

RELEASE = Path(sys.argv[1])

class SlowToDestroy(Node):
    def destroy_node(self):
        deadline = time.monotonic() + 120
        while not RELEASE.exists() and time.monotonic() < deadline:  # outer safety bound
            time.sleep(0.05)
        return super().destroy_node()

def make():
    node = SlowToDestroy("slow_teardown_probe")
    print("ready", flush=True)
    return node

sys.exit(serve(make, "slow_teardown_probe", ["probe"], teardown_report_s=0.2))
"""


def test_a_teardown_past_its_bound_prints_every_threads_stack(tmp_path: Path) -> None:
    release = tmp_path / "release"
    proc = subprocess.Popen([sys.executable, "-c", SLOW_TEARDOWN, str(release)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert proc.stdout is not None and proc.stderr is not None
        assert proc.stdout.readline().strip() == "ready"
        proc.send_signal(signal.SIGINT)
        seen: list[str] = []
        for line in proc.stderr:  # ends at EOF: a process that died says so below
            seen.append(line)
            if "in serve" in line:  # the stack's outer frame: destroy_node came before it
                break
        release.touch()
        _, rest = proc.communicate(timeout=60)
    finally:
        proc.kill()
    err = "".join(seen) + rest
    assert proc.returncode == 0, err
    assert "Timeout (0:00:00.200000)!" in err, err
    assert "in destroy_node" in err and "in serve" in err, err




STUCK_TEARDOWN = """
import json, os, sys, threading, time
from pathlib import Path
from sar_framework.ros.teardown import unstuck_teardown

release, after = Path(sys.argv[1]), float(sys.argv[2])
helper = threading.Thread(target=lambda: release.exists() or time.sleep(120), daemon=True)
helper.start()  # a second thread: the watchdog moves every thread to one CPU
cpus = sorted(os.sched_getaffinity(0))
print(json.dumps({"cpus": cpus}), flush=True)
with unstuck_teardown(stuck_after_s=after):
    deadline = time.monotonic() + 120
    while not release.exists() and time.monotonic() < deadline:  # outer safety bound
        pass  # a teardown that spins, as Fast DDS's participant teardown can
print(json.dumps({"idle_after": os.sched_getscheduler(0) == os.SCHED_IDLE,
                  "cpus_after": sorted(os.sched_getaffinity(0))}), flush=True)
"""


def _policy_and_cpus(pid: int) -> tuple[int, set[frozenset[int]]]:
    tasks = [int(task) for task in os.listdir(f"/proc/{pid}/task")]
    return (os.sched_getscheduler(pid),
            {frozenset(os.sched_getaffinity(task)) for task in tasks})


def test_a_teardown_still_spinning_past_its_bound_yields_to_the_threads_it_waits_for(
        tmp_path: Path) -> None:
    # Fast DDS's participant teardown can spin on a mutex that a discovery callback's thread
    # needs (sar_framework/ros/teardown.py). Past the bound, the watchdog puts the process
    # on one CPU and the spinning thread at idle priority, so that thread preempts it; once
    # the teardown is over, both are as before. (The race itself is the soak's:
    # benchmarks/soak_server_teardown.py.)
    release = tmp_path / "release"
    proc = subprocess.Popen([sys.executable, "-c", STUCK_TEARDOWN, str(release), "0.2"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert proc.stdout is not None
        cpus = set(json.loads(proc.stdout.readline())["cpus"])
        seen = _policy_and_cpus(proc.pid)
        deadline = time.monotonic() + 60
        while seen[0] != os.SCHED_IDLE and time.monotonic() < deadline:  # outer safety bound
            time.sleep(0.05)
            seen = _policy_and_cpus(proc.pid)
        release.touch()
        out, err = proc.communicate(timeout=60)  # outer safety bound
    finally:
        proc.kill()
    assert seen[0] == os.SCHED_IDLE, f"the spinning thread was not moved to idle: {seen}"
    assert len(seen[1]) == 1 and len(next(iter(seen[1]))) == 1, seen  # one CPU for all
    assert proc.returncode == 0, err
    after = json.loads(out)
    assert after == {"idle_after": False, "cpus_after": sorted(cpus)}, after
    assert "still running after 0.2 s" in err, err


def test_a_teardown_within_its_bound_is_left_alone(tmp_path: Path) -> None:
    release = tmp_path / "release"
    release.touch()  # the "teardown" ends at once
    out = subprocess.run([sys.executable, "-c", STUCK_TEARDOWN, str(release), "60"],
                         capture_output=True, text=True, timeout=60,  # outer safety bound
                         check=False)
    assert out.returncode == 0, out.stderr
    cpus = json.loads(out.stdout.splitlines()[0])["cpus"]
    assert json.loads(out.stdout.splitlines()[1]) == {"idle_after": False, "cpus_after": cpus}
    assert "still running" not in out.stderr, out.stderr
