"""``sar-tree watch`` in a real terminal (tmux), attached to a real mission."""

from __future__ import annotations

import importlib.util
import itertools
import os
import re
import shlex
import shutil
import subprocess
import sys
import time
import uuid
from collections.abc import Callable, Iterator
from typing import Any

import py_trees
import pytest
from e2e.helpers import DEFAULT_TREE, REPO
from sar_testing.spin import call_service, ros_node, spin_until

from sar_framework.sim.params import sim_default
from sar_framework.testing.sim_control import set_sim_params

pytestmark = [pytest.mark.ros, pytest.mark.slow,
              pytest.mark.skipif(shutil.which("tmux") is None, reason="tmux is not installed")]


class Terminal:
    """A tmux server of its own (so it takes this test's environment) with one window."""

    def __init__(self, command: list[str], width: int = 120, height: int = 40) -> None:
        self.socket = f"sar-watch-{uuid.uuid4().hex[:8]}"
        env = {k: os.environ[k] for k in ("ROS_DOMAIN_ID", "ROS_AUTOMATIC_DISCOVERY_RANGE",
                                          "SAR_TREE_CACHE_DIR") if k in os.environ}
        exports = " ".join(f"{k}={shlex.quote(v)}" for k, v in env.items())
        shell = (f"cd {shlex.quote(str(REPO))} && env {exports} {shlex.join(command)}; "
                 "echo EXIT=$?; sleep 600")
        self._tmux("new-session", "-d", "-s", "w", "-x", str(width), "-y", str(height), shell)

    def _tmux(self, *args: str) -> str:
        return subprocess.run(["tmux", "-L", self.socket, *args], capture_output=True,
                              text=True, check=True, timeout=10).stdout

    def screen(self) -> str:
        return self._tmux("capture-pane", "-p", "-t", "w")

    def wait_for(self, found: Callable[[str], bool], timeout: float) -> str:
        deadline = time.monotonic() + timeout  # outer safety bound
        while time.monotonic() < deadline:  # outer safety bound
            text = self.screen()
            if found(text):
                return text
            time.sleep(0.2)
        raise AssertionError(f"not on the screen within {timeout} s:\n{self.screen()}")

    def close(self) -> None:
        subprocess.run(["tmux", "-L", self.socket, "kill-server"], capture_output=True,
                       check=False, timeout=10)


@pytest.fixture
def terminal() -> Iterator[Callable[[list[str]], Terminal]]:
    opened: list[Terminal] = []

    def open_terminal(command: list[str]) -> Terminal:
        opened.append(Terminal(command))
        return opened[-1]

    yield open_terminal
    for t in opened:
        t.close()


SAR_TREE = [sys.executable, "-m", "sar_framework"]


def test_watch_without_a_mission_says_so(terminal) -> None:
    screen = terminal([*SAR_TREE, "watch", "--wait", "2"])
    final = screen.wait_for(lambda s: "EXIT=" in s, 30)
    assert "EXIT=1" in final
    assert "no mission ticked on /sar_tree/status within 2 s" in final


def open_snapshot_stream(node, executor) -> str:
    """Open a stream on whichever tree offers one, as py-trees-tree-watcher does; its topic."""
    from py_trees_ros_interfaces.srv import OpenSnapshotStream

    kind = "py_trees_ros_interfaces/srv/OpenSnapshotStream"
    found: list[str] = []

    def offered() -> bool:
        found[:] = [n for n, types in node.get_service_names_and_types() if kind in types]
        return bool(found)

    assert spin_until(executor, offered, 60.0), "no tree offers a snapshot stream"
    request = OpenSnapshotStream.Request()
    request.parameters.snapshot_period = 0.0
    return call_service(node, executor, OpenSnapshotStream, found[0], request).topic_name


SYMBOLS = {1: "-", 2: "*", 3: "✓", 4: "✕"}  # py_trees_ros_interfaces' INVALID..FAILURE
RUNNING = "* NavigateToZone  navigating to zone_"


@pytest.fixture(scope="module")
def watched_mission(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    """One mission, ``sar-tree run --watch`` in a terminal at speed 10 (the simulator's
    default once a zone goal was drawn), followed by ``sar-tree watch`` in a second terminal
    and, where py_trees_ros is installed, by a listener of the runner's snapshot stream.

    Returns the watch's screen while a zone goal runs (``running``) and at its end
    (``final``), the run's own screen at its end (``run_final``), the run's exit code
    (``code``), its report folder (``report``) and the stream's statuses by tick
    (``by_tick``).
    """
    snapshots = importlib.util.find_spec("py_trees_ros_interfaces") is not None
    report = tmp_path_factory.mktemp("watched") / "report"
    screen = Terminal([*SAR_TREE, "watch", "--wait", "60"])
    seen: dict[str, Any] = {"running": "", "final": "", "run_final": "", "by_tick": {},
                            "snapshots": snapshots, "report": report}
    run: Terminal | None = None
    try:
        screen.wait_for(lambda s: "waiting for a mission on /sar_tree/status" in s, 30)
        run = Terminal([*SAR_TREE, "run", str(DEFAULT_TREE), "--speed", "10", "--watch",
                        "--report-dir", str(report)])
        with ros_node("snapshot_listener") as (node, executor):
            if snapshots:
                from py_trees_ros_interfaces.msg import BehaviourTree

                by_tick = seen["by_tick"]
                node.create_subscription(
                    BehaviourTree, open_snapshot_stream(node, executor),
                    lambda m: by_tick.__setitem__(m.statistics.count + 1, sorted(
                        (SYMBOLS[b.status], b.name) for b in m.behaviours)), 100)
            calls = itertools.count()

            def over() -> bool:  # spin_until asks every 10 ms; the screen is read every 20th
                if next(calls) % 20:
                    return False
                text = screen.screen()
                if not seen["running"] and RUNNING in text and "ticks/s" in text:
                    seen["running"] = text
                seen["final"] = text
                return "EXIT=" in text

            # At speed 10 until a zone goal is on the screen, then at the simulator's
            # default (ros2 param set /sar_sim speed): the rest needs no slow run.
            spin_until(executor, lambda: over() or bool(seen["running"]), 150.0)
            if seen["running"]:
                (sped_up,) = set_sim_params(node, executor, speed=sim_default("speed"))
                assert sped_up.successful, sped_up.reason
            spin_until(executor, over, 150.0)
            drawn_tick = re.search(r"search_and_rescue  tick (\d+)", seen["final"])
            if snapshots and drawn_tick:  # its snapshot may still be on its way
                spin_until(executor, lambda: int(drawn_tick.group(1)) in seen["by_tick"],
                           5.0)
        seen["run_final"] = run.wait_for(lambda s: "EXIT=" in s, 60)
        seen["code"] = int(re.search(r"EXIT=(\d+)", seen["run_final"]).group(1))
    finally:
        if run is not None:
            run.close()
        screen.close()
    return seen


def test_run_watch_draws_the_tree_instead_of_progress_lines(watched_mission) -> None:
    final = watched_mission["run_final"]
    assert "EXIT=0" in final
    assert "mission over: SUCCESS" in final
    assert "sar-tree run: Mission SUCCESS" in final
    assert "runner |" not in final  # no progress lines while the tree is drawn
    assert (watched_mission["report"] / "mission.json").is_file()


def test_watch_follows_a_mission_and_exits_when_it_is_over(watched_mission) -> None:
    running, final = watched_mission["running"], watched_mission["final"]
    assert running, f"no screen with a zone goal running:\n{final}"
    assert "search_and_rescue  tick " in running
    assert "* MissionOrReturnToBase [selector]" in running
    assert "running branch: MissionOrReturnToBase → Patrol → NavigateToZone" in running
    assert "zone zone_" in running
    assert "blackboard: no keys written by the leaves" in running
    assert "EXIT=" in final, final
    assert watched_mission["code"] == 0
    assert "EXIT=0" in final
    assert "✓ NavigateToBase  Reached base station." in final
    assert "mission over: SUCCESS" in final
    assert "sar-tree watch: the mission is over;" in final


def test_watch_shows_what_the_snapshot_stream_says(watched_mission) -> None:
    if not watched_mission["snapshots"]:
        pytest.skip("py_trees_ros is not installed")
    assert set(SYMBOLS.values()) == {py_trees.display.unicode_symbols[s]
                                     for s in py_trees.common.Status}
    final, by_tick = watched_mission["final"], watched_mission["by_tick"]
    assert watched_mission["code"] == 0
    assert "EXIT=0" in final and "mission over: SUCCESS" in final
    words = " ".join(final.split())  # the source line may wrap
    assert "py_trees_ros snapshots on /sar_mission_runner/snapshot_streams/" in words
    tick = int(re.search(r"search_and_rescue  tick (\d+)", final).group(1))
    drawn = sorted(re.findall(r"── (\S) (\S+)", final))
    assert ("✓", "NavigateToBase") in drawn and len(drawn) > 10
    # every node, with the status the stream gave at that tick
    assert drawn == by_tick.get(tick), (final, tick, sorted(by_tick)[-3:])
