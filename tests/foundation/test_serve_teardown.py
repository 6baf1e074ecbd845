"""A server whose teardown hangs past its bound says where, and ends all the same (code 0).

Fast DDS's participant teardown can hang in the main thread while it holds the GIL
(``sar_framework/ros/teardown.py``): the probes here hang the same way, in C with the GIL
held, where no Python signal handler or thread can run, and in Python too. The race itself
is the soak's: ``benchmarks/soak_server_teardown.py``.
"""

from __future__ import annotations

import signal
import subprocess
import sys

import pytest

pytestmark = pytest.mark.ros

HANGING_TEARDOWN = """
import ctypes, sys, time
from rclpy.node import Node
from sar_framework.ros.serve import serve

HOW = sys.argv[1]

class HangsInDestroy(Node):
    def destroy_node(self):
        if HOW == "c":  # PyDLL keeps the GIL during the call, as rclpy's destroy does
            ctypes.PyDLL(None).sleep(600)
        else:
            deadline = time.monotonic() + 600
            while time.monotonic() < deadline:  # outer safety bound
                time.sleep(0.05)
        return super().destroy_node()

def make():
    node = HangsInDestroy("hanging_teardown_probe")
    print("ready", flush=True)
    return node

sys.exit(serve(make, "hanging_teardown_probe", ["probe"], teardown_bound_s=0.5))
"""


@pytest.mark.parametrize("how", ["c", "python"])
def test_a_teardown_past_its_bound_prints_the_stacks_and_ends_the_process_with_0(
        how: str) -> None:
    proc = subprocess.Popen([sys.executable, "-c", HANGING_TEARDOWN, how],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert proc.stdout is not None
        assert proc.stdout.readline().strip() == "ready"
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=120)  # outer safety bound (ends after 0.5 s)
    finally:
        proc.kill()
    assert proc.returncode == 0, err
    assert "teardown still running after 0.5 s" in err, err
    assert "in destroy_node" in err and "in serve" in err, err  # every thread's stack


QUICK_TEARDOWN = """
from sar_framework.ros.teardown import bounded_teardown
with bounded_teardown(60.0):
    pass
print("after", flush=True)
"""


def test_a_teardown_within_its_bound_goes_on_as_usual() -> None:
    done = subprocess.run([sys.executable, "-c", QUICK_TEARDOWN], capture_output=True,
                          text=True, timeout=60, check=False)  # outer safety bound
    assert (done.returncode, done.stdout, done.stderr) == (0, "after\n", "")
