"""A server whose teardown hangs says where: every thread's stack, on stderr."""

from __future__ import annotations

import signal
import subprocess
import sys

import pytest

pytestmark = pytest.mark.ros

SLOW_TEARDOWN = """
import sys, time
from rclpy.node import Node
from sar_framework.ros.serve import serve

class SlowToDestroy(Node):
    def destroy_node(self):
        time.sleep(2.0)  # longer than the report bound below: the teardown 'hangs'
        return super().destroy_node()

def make():
    node = SlowToDestroy("slow_teardown_probe")
    print("ready", flush=True)
    return node

sys.exit(serve(make, "slow_teardown_probe", ["probe"], teardown_report_s=0.2))
"""


def test_a_teardown_past_its_bound_prints_every_threads_stack() -> None:
    proc = subprocess.Popen([sys.executable, "-c", SLOW_TEARDOWN], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    try:
        assert proc.stdout is not None
        assert proc.stdout.readline().strip() == "ready"
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=60)
    finally:
        proc.kill()
    assert proc.returncode == 0, err
    assert "Timeout (0:00:00.200000)!" in err, err
    assert "in destroy_node" in err and "in serve" in err, err
