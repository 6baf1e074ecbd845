"""A Ctrl-C that arrives twice (terminal and launch) still ends our processes with 0.

``ros2 launch`` without a terminal on stdin sends each child SIGINT after the terminal's
own; Python's finalization puts the default action back for every signal with a Python
handler, so a late second SIGINT ended a process that was stopping cleanly with -2 (the
report server, about 1 launch Ctrl-C in 5). Each test below sends SIGINT every few
milliseconds until the process has ended: every moment of its stop, finalization included,
meets one.
"""

from __future__ import annotations

import os
import signal
import time
from pathlib import Path

import pytest
from sar_testing.processes import NodeProcess

REPO = Path(__file__).resolve().parents[2]
#: Between two SIGINTs of the flood.
FLOOD_PERIOD_S = 0.005

SLOW_TO_FINALIZE = """
import time
from sar_framework.stop_signals import stop_on_signals

class SlowToFinalize:
    def __del__(self):  # module teardown, after Python has reset its signal handlers
        print("finalizing", flush=True)
        time.sleep(0.3)

keep = SlowToFinalize()
stop = stop_on_signals()
print("ready", flush=True)
while not stop:
    time.sleep(0.01)
"""


def interrupt_until_ended(process: NodeProcess, bound_s: float = 20.0) -> int:
    """Send SIGINT to ``process`` every few milliseconds until it ends; its exit code."""
    deadline = time.monotonic() + bound_s
    while process.returncode() is None and time.monotonic() < deadline:  # outer safety bound
        process.send_signal(signal.SIGINT)
        time.sleep(FLOOD_PERIOD_S)
    return process.wait(timeout=10)


def test_a_stop_signal_then_sigints_until_the_end_exit_0(tmp_path: Path) -> None:
    for round_ in range(3):
        script = NodeProcess(["-c", SLOW_TO_FINALIZE], f"plain{round_}", log_dir=tmp_path,
                             env={"PYTHONPATH": str(REPO)}).start()
        script.wait_for_output("ready")
        assert interrupt_until_ended(script) == 0, script.output


def test_sigterm_still_ends_a_process_that_is_stopping(tmp_path: Path) -> None:
    """SIGINT is ignored once stopping; SIGTERM stays the escalation of a slow stop."""
    hanging = SLOW_TO_FINALIZE.replace("time.sleep(0.3)", "time.sleep(60)")
    script = NodeProcess(["-c", hanging], "hanging", log_dir=tmp_path,
                         env={"PYTHONPATH": str(REPO)}).start()
    script.wait_for_output("ready")
    script.send_signal(signal.SIGINT)
    script.wait_for_output("finalizing")  # in finalization now, sleeping
    script.send_signal(signal.SIGINT)
    assert script.returncode() is None
    script.send_signal(signal.SIGTERM)
    assert script.wait(timeout=10) == -signal.SIGTERM


@pytest.mark.ros
@pytest.mark.parametrize("module", ["sar_plugins.sar.servers.report_survivor_server",
                                    "sar_plugins.sar.servers.detect_survivor_server",
                                    "sar_framework.sim"])
def test_a_process_interrupted_until_it_has_ended_exits_0(tmp_path: Path, module: str) -> None:
    ros_args = (["--ros-args", "-p", f"report_file:={tmp_path / 'reports.jsonl'}"]
                if module.endswith("report_survivor_server") else [])
    server = NodeProcess(["-m", module, *ros_args], "server", log_dir=tmp_path).start()
    try:
        server.wait_for_output("ready", timeout=30)
        assert interrupt_until_ended(server) == 0, server.output
    finally:
        server.stop()
    assert "Traceback" not in server.output, server.output


def test_the_stop_flag_ignores_sigint_once_stopping() -> None:
    """The one stop helper every process uses (runner, simulator, servers, recorder)."""
    from sar_framework.stop_signals import StopSignals

    previous = {sig: signal.getsignal(sig) for sig in (signal.SIGINT, signal.SIGTERM)}
    try:
        stop = StopSignals().install()
        assert not stop
        os.kill(os.getpid(), signal.SIGINT)
        assert stop and stop.name == "SIGINT"
        assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
        assert signal.getsignal(signal.SIGTERM) is not signal.SIG_IGN
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
