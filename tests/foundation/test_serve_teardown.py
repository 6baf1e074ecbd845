"""A server whose teardown hangs says where: every thread's stack, on stderr."""

from __future__ import annotations

import signal
import subprocess
import sys
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
