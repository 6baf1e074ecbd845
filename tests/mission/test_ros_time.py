"""Durations in trees follow the injected clock (the node's ROS time), not wall seconds."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import py_trees
from py_trees.common import Status
from sar_testing.manual_clock import ManualClock

from sar_framework import load_tree
from sar_framework.engine.building.control_build import CLOCK_KEY
from sar_framework.engine.building.py_trees_build import ClockTimeout
from sar_framework.testing import declared_leaf

TREE = """\
format: 1
name: timed
root:
  sequence:
    name: Steps
    memory: true
    children:
      - Dwell: {name: Dwell, duration: 2.0}
      - timeout:
          name: Within3s
          duration: 3.0
          child: {Dwell: {name: Long, duration: 100.0}}
"""


def test_wait_and_timeout_follow_the_clock_not_the_wall(tmp_path: Path) -> None:
    """Regression: timeouts counted wall seconds (a 1.5 s timeout was 30 s simulated at 20x)."""
    path = tmp_path / "t.yaml"
    path.write_text(TREE)
    clock = ManualClock(1000.0)
    loaded = load_tree(path, context={CLOCK_KEY: clock})
    assert isinstance(loaded.behaviours["0.1"], ClockTimeout)
    tree = py_trees.trees.BehaviourTree(loaded.root)
    tree.setup(node=clock.node())
    seen = []
    for _ in range(8):  # half a simulated second per tick, no wall time passes
        tree.tick()
        seen.append((clock.now - 1000.0, loaded.behaviours["0.0"].status.name,
                     loaded.root.status.name))
        clock.now += 0.5
    # Dwell runs until 2.0 s, then Within3s runs Long until 2.0 + 3.0 s and fails
    assert [s for t, s, _ in seen if t < 2.0] == ["RUNNING"] * 4
    assert seen[4][1] == "SUCCESS"
    assert loaded.root.status == Status.RUNNING
    while loaded.root.status == Status.RUNNING and clock.now < 1010.0:
        tree.tick()
        clock.now += 0.5
    assert loaded.root.status == Status.FAILURE
    assert clock.now - 0.5 - 1000.0 == 5.5  # the first tick past 2.0 + 3.0
    assert loaded.behaviours["0.1"].feedback_message == "timed out"
    assert loaded.behaviours["0.1.0"].status == Status.INVALID  # halted


def test_without_a_clock_timeout_is_py_trees_own(tmp_path: Path) -> None:
    path = tmp_path / "t.yaml"
    path.write_text(TREE)
    loaded = load_tree(path)
    assert type(loaded.behaviours["0.1"]) is py_trees.decorators.Timeout


class FakeClient:
    """A client whose server never becomes ready."""

    service_name = "/detect_survivor"  # rclpy's Client gives the resolved name

    def service_is_ready(self) -> bool:
        return False

    def server_is_ready(self) -> bool:
        return False


def test_a_leaf_s_own_bounds_follow_the_clock_not_the_wall(monkeypatch) -> None:
    """Regression: server_timeout_s, navigation_timeout_s and response_timeout_s counted wall
    seconds while timeout decorators counted ROS time, so which fired first changed with
    --speed (at 10x a 10 s detect bound beat a 180 s visit timeout; at 20x it did not)."""
    from sar_plugins.sar.leaves.navigate_to_zone import NavigateToZone
    from sar_plugins.sar.zone_manager import ZoneManager

    from sar_framework.leaves import PolledServiceCall

    clock = ManualClock(1000.0)
    node = clock.node()
    node.create_client = lambda *_args: FakeClient()
    node.get_logger = lambda: SimpleNamespace(info=print, warning=print)
    call = PolledServiceCall(node, object, "/detect_survivor", server_timeout_s=10.0,
                             response_timeout_s=10.0)
    call.start()
    clock.now += 9.9
    assert call.poll(lambda: None) is None  # no wall second needed to pass
    clock.now += 0.2
    result = call.poll(lambda: None)
    assert result is not None
    assert result.error == "/detect_survivor service not available after 10.0 s"

    zones = ZoneManager([{"id": "zone_a", "x": 1.0, "y": 2.0, "yaw": 0.0}],
                        {"x": 0.0, "y": 0.0, "yaw": 0.0})
    leaf = declared_leaf(NavigateToZone, "Go", zone_manager=zones, server_timeout_s=10.0)
    import rclpy.action

    monkeypatch.setattr(rclpy.action, "ActionClient", lambda *_args: FakeClient())
    leaf.setup(node=node)
    leaf.tick_once()
    clock.now += 9.9
    leaf.tick_once()
    assert leaf.status == Status.RUNNING
    clock.now += 0.2
    leaf.tick_once()
    assert leaf.status == Status.FAILURE
    assert leaf.feedback_message == "navigate_to_pose server not available after 10.0 s"
