"""Nav2 start-up (AMCL seed + lifecycle wait) against a fake Nav2 in a child process."""

from __future__ import annotations

from pathlib import Path

import pytest
from sar_testing.processes import NodeProcess

from sar_framework.runner.nav2_startup import (
    InitialPose,
    Nav2StartupError,
    StartupInterrupted,
    basic_navigator_class,
    seed_amcl_and_wait_for_nav2,
)

pytestmark = pytest.mark.ros
FAKE = str(Path(__file__).resolve().parents[1] / "sar_testing" / "nodes" / "fake_nav2_lifecycle.py")


class Lines:
    """Collects what the start-up logs."""

    def __init__(self) -> None:
        self.lines: list[str] = []

    def info(self, message: str) -> None:
        self.lines.append(message)


def wait(ros, **kwargs) -> None:
    node, _executor = ros
    seed_amcl_and_wait_for_nav2(context=node.context, **kwargs)


def test_basic_navigator_is_used_exactly_when_nav2_simple_commander_imports():
    # The fallback tier has no nav2_simple_commander; the real-stack tier takes the other path.
    try:
        from nav2_simple_commander.robot_navigator import BasicNavigator
    except ImportError:
        BasicNavigator = None  # noqa: N806 - the class's own name
    assert basic_navigator_class() is BasicNavigator


def test_seeds_amcl_and_waits_for_bt_navigator(ros, tmp_path):
    logger = Lines()
    with NodeProcess([FAKE, "--bt-active-after", "4"], "nav2", log_dir=tmp_path) as fake:
        fake.wait_for_output("ready")
        wait(ros, pose=InitialPose(1.0, -2.0, 0.5), timeout_s=40.0, logger=logger)
        fake.wait_for_output(r"initialpose x=1\.00 y=-2\.00 yaw=0\.50 frame=map")
        # It asked while bt_navigator was inactive, and went on only once it was active.
        fake.wait_for_output("bt_navigator answered inactive")
        fake.wait_for_output("bt_navigator answered active")
    assert "bt_navigator is ACTIVE: Nav2 is ready" in logger.lines
    assert any("answered on /amcl_pose" in line for line in logger.lines)


def test_no_nav2_is_a_bounded_clear_failure(ros):
    with pytest.raises(Nav2StartupError) as err:
        wait(ros, timeout_s=2.0)
    assert str(err.value) == ("amcl never reported ACTIVE (/amcl/get_state never appeared) "
                              "within 2 s: is Nav2 (or the simulator) running?")


def test_bt_navigator_that_stays_inactive(ros, tmp_path):
    with NodeProcess([FAKE, "--bt-never-active"], "nav2", log_dir=tmp_path) as fake:
        fake.wait_for_output("ready")
        with pytest.raises(Nav2StartupError) as err:
            wait(ros, timeout_s=6.0)
    assert str(err.value) == ("bt_navigator never reported ACTIVE (last state: inactive) "
                              "within 6 s: is Nav2 (or the simulator) running?")


def test_amcl_that_never_answers_the_seed(ros, tmp_path):
    with NodeProcess([FAKE, "--ignore-initialpose"], "nav2", log_dir=tmp_path) as fake:
        fake.wait_for_output("ready")
        with pytest.raises(Nav2StartupError, match=r"^amcl never answered /initialpose on "
                           r"/amcl_pose within 6 s: is Nav2"):
            wait(ros, timeout_s=6.0)
        fake.wait_for_output("initialpose x=0.00 y=0.00 yaw=0.00 frame=map")
        assert fake.output.count("initialpose x=") >= 2, "the seed is re-sent until answered"


def test_stop_request_interrupts_the_wait(ros):
    """A stop request ends the wait at once, long before its bound (no Nav2 runs here)."""
    asked = []

    def should_stop() -> bool:
        asked.append(True)
        return len(asked) >= 3  # asked while waiting, then a stop request

    with pytest.raises(StartupInterrupted):
        wait(ros, timeout_s=600.0, should_stop=should_stop)  # outer safety bound
    assert len(asked) == 3


def test_a_get_state_reply_lost_by_dds_is_asked_again(ros, tmp_path):
    logger = Lines()
    with NodeProcess([FAKE, "--bt-drop-first", "1"], "nav2", log_dir=tmp_path) as fake:
        fake.wait_for_output("ready")
        wait(ros, timeout_s=60.0, logger=logger)  # outer safety bound
        fake.wait_for_output("get_state request 1 left unanswered")
    assert "bt_navigator is ACTIVE: Nav2 is ready" in logger.lines


BASIC_NAVIGATOR_SCRIPT = """
import sys

import rclpy
from sar_framework.runner import nav2_startup

class Printer:
    info = staticmethod(print)

navigator_class = nav2_startup.basic_navigator_class()

asked = []  # (service, future) of every request BasicNavigator sent

class Spy(navigator_class):
    def create_client(self, srv_type, srv_name, **kwargs):
        client = super().create_client(srv_type, srv_name, **kwargs)
        send = client.call_async

        def call_async(request):
            asked.append((srv_name, send(request)))
            return asked[-1][1]

        client.call_async = call_async
        return client

nav2_startup.basic_navigator_class = lambda: Spy
rclpy.init()
nav2_startup.seed_amcl_and_wait_for_nav2(timeout_s=25.0, logger=Printer(),
                                         ask_first=sys.argv[1] == "ask-first")
print("STARTED", flush=True)
for service, future in asked:  # ANSWER <service> <label>, or "none" while unanswered
    answer = future.result() if future.done() else None
    print("ANSWER", service, answer.current_state.label if answer else "none", flush=True)
"""


#: The runner's end after the start: the context shut down, then a few seconds of life (the
#: stuck BasicNavigator's loop sleeps 2 s between two asks).
SHUT_DOWN_AND_LIVE_ON = "rclpy.shutdown()\nimport time\ntime.sleep(3.0)\n"


@pytest.mark.slow
@pytest.mark.skipif(basic_navigator_class() is None,
                    reason="real-stack tier: nav2_simple_commander is not installed")
@pytest.mark.parametrize("end", ["", SHUT_DOWN_AND_LIVE_ON], ids=["exit", "shutdown-then-live"])
def test_basic_navigator_stuck_on_a_lost_reply_does_not_stall_the_start(tmp_path, end):
    """BasicNavigator waits for a get_state reply forever; the start-up goes on without it.

    It runs in a process of its own (BasicNavigator needs the default context), which must
    then exit cleanly: a thread left inside rcl's wait used to abort the interpreter, and
    one that outlived the context's shutdown asked rclpy for a global executor it could no
    longer build ("Exception ignored in: Executor.__del__" and a traceback, under launch).
    """
    import subprocess
    import sys

    with NodeProcess([FAKE, "--bt-drop-first", "1"], "nav2", log_dir=tmp_path) as fake:
        fake.wait_for_output("ready")
        # BasicNavigator asks first: its request is the one left unanswered.
        # BasicNavigator sleeps 2 s per lifecycle answer: 120 s is an outer safety bound.
        done = subprocess.run([sys.executable, "-c", BASIC_NAVIGATOR_SCRIPT + end,
                               "basic-navigator-first"],
                              capture_output=True, text=True, timeout=120, check=False)
        fake.wait_for_output("get_state request 1 left unanswered")
    out = done.stdout + done.stderr
    assert done.returncode == 0, out
    assert "STARTED" in out and "going on" in out, out
    assert "terminate called" not in out and "Traceback" not in out, out


def _answers(out: str) -> list[str]:
    """The get_state answers BasicNavigator received, ``<service> <label>`` each."""
    return [line.split(" ", 1)[1] for line in out.splitlines() if line.startswith("ANSWER ")]


@pytest.mark.slow
@pytest.mark.skipif(basic_navigator_class() is None,
                    reason="real-stack tier: nav2_simple_commander is not installed")
@pytest.mark.parametrize("fake_args", [["--bt-active-after", "3"], ["--bt-drop-first", "1"]],
                         ids=["navigator-inactive-at-first", "first-reply-lost"])
def test_basic_navigator_asks_each_node_once_when_it_is_already_active(tmp_path, fake_args):
    """Asked first (re-sending, without sleeps), both nodes are ACTIVE when BasicNavigator
    asks: one answer each, ``active``, so each of its 2 s sleeps is paid once; a reply lost
    before (the navigator's first) is asked again by the start-up, not by BasicNavigator."""
    import subprocess
    import sys

    with NodeProcess([FAKE, *fake_args], "nav2", log_dir=tmp_path) as fake:
        fake.wait_for_output("ready")
        done = subprocess.run([sys.executable, "-c", BASIC_NAVIGATOR_SCRIPT, "ask-first"],
                              capture_output=True, text=True, timeout=120,  # outer safety bound
                              check=False)
    out = done.stdout + done.stderr
    assert done.returncode == 0, out
    assert "STARTED" in out and "going on" not in out, out
    assert _answers(out) == ["amcl/get_state active", "bt_navigator/get_state active"], out
