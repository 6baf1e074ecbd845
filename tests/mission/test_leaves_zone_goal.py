"""SetZoneGoal and MarkZoneReached: the zone's pose through the blackboard, the visit told."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from py_trees.blackboard import Blackboard
from py_trees.common import Status
from sar_plugins.sar.events import SarKind
from sar_plugins.sar.zone_manager import ZoneManager
from sar_testing.leaf_harness import spec_zone_manager

from sar_framework.engine.api import LoadedTree, load_tree
from sar_framework.events.emitter import EventEmitter
from sar_framework.events.event import EventKind

pytest.importorskip("geometry_msgs.msg", reason="the goal is a geometry_msgs/PoseStamped")

TREE = """format: 1
blackboard:
  zone_goal: {type: geometry_msgs/msg/PoseStamped}
root:
  sequence:
    name: Visit
    memory: true
    children:
      - SetZoneGoal: {goal: "{zone_goal}", frame_id: %s}
      - subtree: {tree: Drive, ports: {target: "{zone_goal}"}}
      - MarkZoneReached: {}
subtrees:
  Drive:
    ports:
      target: {type: geometry_msgs/msg/PoseStamped, direction: input}
    blackboard:
      seen: {type: int, initial: 0}
    root:
      Script: {code: "seen := 1"}
"""


def visit_tree(tmp_path: Path, zones: ZoneManager, frame: str = "map") -> LoadedTree:
    tree = tmp_path / "visit.yaml"
    tree.write_text(TREE % frame)
    Blackboard.storage.clear()
    return load_tree(tree, {"zone_manager": zones})


def test_the_current_zones_pose_reaches_the_subtree_port(tmp_path: Path) -> None:
    zones = spec_zone_manager()
    zones.advance()  # zone_b (3.5, 3.0, yaw 1.57)
    loaded = visit_tree(tmp_path, zones, frame="odom")
    loaded.root.tick_once()
    assert loaded.root.status == Status.SUCCESS
    goal = Blackboard.storage["/zone_goal"]
    assert goal.header.frame_id == "odom"
    assert (goal.pose.position.x, goal.pose.position.y) == (3.5, 3.0)
    yaw = 2 * math.atan2(goal.pose.orientation.z, goal.pose.orientation.w)
    assert yaw == pytest.approx(1.57)


def test_announces_the_zone_and_marks_it_reached(tmp_path: Path) -> None:
    zones = spec_zone_manager()
    told: list[tuple] = []
    zones.observe(lambda kind, zone: told.append((kind, zone["id"])))
    loaded = visit_tree(tmp_path, zones)
    events = EventEmitter()
    loaded.root.setup_with_descendants()
    for behaviour in loaded.root.iterate():
        behaviour.setup(events=events)
    loaded.root.tick_once()
    assert loaded.root.status == Status.SUCCESS
    assert told == [(SarKind.ZONE_REACHED, "zone_a")]
    navigation = [(e.kind, e.value("zone_id"), e.message, e.position) for e in events.emitted]
    assert navigation == [(EventKind.NAVIGATION, "zone_a", "--- Zone 1/4: zone_a (-3.00, 3.00) ---",
                           (-3.0, 3.0, 0.0))]
    mark = next(b for b in loaded.root.iterate() if type(b).__name__ == "MarkZoneReached")
    assert mark.feedback_message == "Reached zone_a."


def test_both_fail_when_no_zone_is_left(tmp_path: Path) -> None:
    from sar_plugins.sar.leaves.zone_goal import MarkZoneReached

    zones = spec_zone_manager([])
    loaded = visit_tree(tmp_path, zones)
    loaded.root.tick_once()
    assert loaded.root.status == Status.FAILURE
    setter = next(b for b in loaded.root.iterate() if type(b).__name__ == "SetZoneGoal")
    assert setter.feedback_message == "no zone left to set as the goal"
    assert "/zone_goal" not in Blackboard.storage
    mark = MarkZoneReached("Mark", zone_manager=zones)
    mark.tick_once()
    assert mark.status == Status.FAILURE


def test_an_unbound_goal_port_is_a_validation_error(tmp_path: Path) -> None:
    from sar_framework.engine.api import validate

    tree = tmp_path / "bad.yaml"
    tree.write_text("format: 1\nroot:\n  SetZoneGoal: {goal: nowhere}\n")
    problems = [str(d) for d in validate(tree).diagnostics]
    assert any("bad.yaml:3:" in p and "output port 'goal' must be bound to an entry" in p
               for p in problems), problems
