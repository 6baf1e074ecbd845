"""Ctrl-C in the middle of the mission under ``ros2 launch``: the scenario and its checks.

One scenario for the real-stack test (``tests/ros_stack/test_ros2_launch.py``) and the soak
(``benchmarks/soak_launch_ctrl_c.py``): start ``ros2 launch sar_framework
search_and_rescue.launch.py nav2:=embedded speed:=1.0``, wait for the first zone, check that
every node name is listed once, then SIGINT the launch's process group, as a terminal's
Ctrl-C does (launch, without a terminal on stdin, sends each child SIGINT once more).
"""

from __future__ import annotations

import contextlib
import dataclasses
import os
import re
import signal
import subprocess
import sys
import time
from collections.abc import Sequence
from pathlib import Path

from sar_testing.ros2_cli import attempt
from sar_testing.temp_dirs import launch_env

ROS2 = Path(sys.prefix) / "bin" / "ros2"
LAUNCH = ["launch", "sar_framework", "search_and_rescue.launch.py", "nav2:=embedded"]
#: Every node the mission's processes hold.
NODES = {"/sar_mission_runner", "/sar_sim", "/amcl", "/bt_navigator",
         "/detect_survivor_server", "/report_survivor_server"}
#: How the test lists them: no daemon, so nothing is left running after the test.
NODE_LIST = (str(ROS2), "node", "list", "--no-daemon", "--spin-time", "3")
#: The launch's processes, each of which must finish cleanly.
PROCESSES = ("sar-sim", "sar-detect-survivor-server", "sar-report-survivor-server",
             "sar-mission-runner")


def launch(tmp_path: Path, *arguments: str) -> subprocess.Popen[str]:
    """Start the launch in a session of its own, its output (both streams) on a pipe."""
    env = launch_env(tmp_path, ROS_LOG_DIR=str(tmp_path / "ros-log"),
                     RCUTILS_COLORIZED_OUTPUT="0", PYTHONUNBUFFERED="1")
    # No terminal on stdin, as in CI: launch is then --noninteractive and forwards SIGINT.
    return subprocess.Popen(
        [str(ROS2), *LAUNCH, f"report_file:={tmp_path / 'reports.jsonl'}", *arguments],
        stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
        env=env, start_new_session=True)


def kill_group(proc: subprocess.Popen[str]) -> None:
    """SIGKILL what is left of the launch's process group and reap the launch."""
    # Also after launch itself exited: a launch that failed can leave a child behind.
    with contextlib.suppress(ProcessLookupError):
        os.killpg(proc.pid, signal.SIGKILL)
    proc.communicate(timeout=30)


def node_names(expected: set[str], bound_s: float, command: Sequence[str] = NODE_LIST,
               hang_s: float = 30.0) -> list[str]:
    """``ros2 node list``, asked again until it names every expected node or the bound ends.

    A listing that hangs past ``hang_s`` (ten times its spin time) is killed and asked again.
    """
    deadline = time.monotonic() + bound_s
    listed: list[str] = []
    while True:
        done = attempt(command, hang_s)
        if done is not None:
            assert done.returncode == 0, done.stdout + done.stderr
            listed = done.stdout.split()
        if expected <= set(listed) or time.monotonic() > deadline:  # outer safety bound
            return listed


@dataclasses.dataclass
class CtrlCRun:
    """What one Ctrl-C scenario saw.

    Attributes:
        reached_zone: Whether the mission printed ``--- Zone 1/4`` before Ctrl-C.
        listed: ``ros2 node list`` just before Ctrl-C (empty if the zone was not reached).
        returncode: The launch's exit code.
        output: Everything the launch printed.
    """

    reached_zone: bool
    listed: list[str]
    returncode: int | None
    output: str

    def failures(self) -> list[str]:
        """Every way this run was not clean, each naming its process where there is one."""
        if not self.reached_zone:
            return [f"the mission did not reach zone 1:\n{self.output}"]
        found: list[str] = []
        missing = NODES - set(self.listed)
        if missing:
            found.append(f"node list lacks {sorted(missing)}")
        if len(self.listed) != len(set(self.listed)):
            found.append(f"a node name is listed twice: {self.listed}")
        if self.returncode != 0:
            found.append(f"ros2 launch exited with {self.returncode}")
        if "Traceback" in self.output or "KeyboardInterrupt" in self.output:
            found.append("a traceback or KeyboardInterrupt was printed")
        for process in PROCESSES:
            if not re.search(rf"\[{process}-\d\]: process has finished cleanly", self.output):
                died = re.search(rf"\[{process}-\d\]: process has died.*", self.output)
                found.append(f"{process}: {died.group(0) if died else 'no clean finish'}")
        if "process has died" in self.output and not any("died" in f for f in found):
            found.append("a process has died")  # the runner's was "exit code 130"
        return found


def ctrl_c_mid_mission(tmp_path: Path) -> CtrlCRun:
    """Run the scenario once: launch, wait for zone 1, list the nodes, Ctrl-C, collect."""
    proc = launch(tmp_path, "speed:=1.0")  # a slow mission: still running when we look
    try:
        lines: list[str] = []
        deadline = time.monotonic() + 90
        assert proc.stdout is not None
        while time.monotonic() < deadline:  # outer safety bound
            line = proc.stdout.readline()
            lines.append(line)
            if "--- Zone 1/4" in line or not line:
                break
        if not any("--- Zone 1/4" in line for line in lines):
            return CtrlCRun(False, [], proc.poll(), "".join(lines))
        listed = node_names(NODES, 120.0)  # discovery of a busy process can take a while
        os.killpg(proc.pid, signal.SIGINT)  # a terminal's Ctrl-C: launch and its children
        rest, _ = proc.communicate(timeout=60)
        return CtrlCRun(True, listed, proc.returncode, "".join(lines) + rest)
    finally:
        kill_group(proc)
