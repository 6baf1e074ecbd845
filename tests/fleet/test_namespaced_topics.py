"""The runner's event and status topics are relative: ``/robot1/...`` in ``/robot1``.

A single robot's runner (the root namespace) keeps ``/sar_mission/events`` and
``/sar_tree/status``, which every reader (sar-tree run's outcome, recording, watch, studio)
reads; a fleet's runners each publish under their own namespace (docs/how-to/fleet.md).
"""

from __future__ import annotations

from pathlib import Path

import py_trees
import pytest
from sar_testing.spin import ros_node, spin_until

from sar_framework import load_tree
from sar_framework.events.event import (
    EVENT_TOPIC,
    EVENT_TOPIC_NAME,
    EventKind,
    MissionEvent,
    in_namespace,
)
from sar_framework.runner.tree_status import STATUS_TOPIC, STATUS_TOPIC_NAME

TREE_FILE = Path(__file__).resolve().parents[1] / "watch" / "watched.yaml"
LEAVES = TREE_FILE.with_name("watch_leaves.py")


@pytest.mark.parametrize(("namespace", "expected"), [
    ("", "/sar_mission/events"), ("/", "/sar_mission/events"),
    ("robot1", "/robot1/sar_mission/events"), ("/robot2/", "/robot2/sar_mission/events")])
def test_in_namespace_names_the_relative_topic_in_a_namespace(namespace: str,
                                                              expected: str) -> None:
    assert in_namespace(EVENT_TOPIC_NAME, namespace) == expected


def test_the_root_namespace_names_are_the_ones_readers_always_used() -> None:
    assert EVENT_TOPIC == "/sar_mission/events" == in_namespace(EVENT_TOPIC_NAME)
    assert STATUS_TOPIC == "/sar_tree/status" == in_namespace(STATUS_TOPIC_NAME)
    assert not EVENT_TOPIC_NAME.startswith("/") and not STATUS_TOPIC_NAME.startswith("/")


@pytest.mark.ros
@pytest.mark.parametrize("namespace", ["", "robot1"])
def test_a_runner_s_publishers_go_out_in_its_namespace(namespace: str) -> None:
    from rclpy.node import Node
    from sar_interfaces.msg import MissionEvent as EventMsg
    from std_msgs.msg import String

    from sar_framework.runner.event_topic import EventPublisher, event_qos
    from sar_framework.runner.tree_status import TreeStatusPublisher

    py_trees.blackboard.Blackboard.clear()
    loaded = load_tree(TREE_FILE, plugin_paths=[LEAVES])
    tree = py_trees.trees.BehaviourTree(loaded.root)
    with ros_node("topics_reader") as (reader, executor):
        runner = Node("sar_mission_runner", namespace=namespace, context=reader.context)
        executor.add_node(runner)
        status_topic = in_namespace(STATUS_TOPIC_NAME, namespace)
        event_topic = in_namespace(EVENT_TOPIC_NAME, namespace)
        statuses: list[str] = []
        events: list[object] = []
        reader.create_subscription(String, status_topic, lambda m: statuses.append(m.data), 10)
        reader.create_subscription(EventMsg, event_topic, events.append, event_qos())
        TreeStatusPublisher(runner, loaded.spec, loaded.behaviours).attach(tree)
        publish = EventPublisher(runner)
        assert {p.topic_name for p in runner.publishers} >= {status_topic, event_topic}
        assert spin_until(executor, lambda: reader.count_publishers(event_topic) == 1
                          and reader.count_publishers(status_topic) == 1, 10.0)
        assert spin_until(executor, lambda: runner.count_subscribers(event_topic) >= 1, 10.0)
        publish(MissionEvent(kind=EventKind.NOTE, seq=1, sim_s=0.0, wall_s=0.0, message="hi"))
        tree.tick()
        assert spin_until(executor, lambda: bool(statuses) and bool(events), 10.0)
        if namespace:  # nothing in the root: a fleet's runners do not share a topic
            assert reader.count_publishers(STATUS_TOPIC) == 0
            assert reader.count_publishers(EVENT_TOPIC) == 0


@pytest.mark.ros
def test_sar_tree_watch_follows_the_runner_of_a_namespace() -> None:
    import subprocess
    import sys

    result = subprocess.run(
        [sys.executable, "-m", "sar_framework", "watch", "--namespace", "robot1", "--wait", "1"],
        capture_output=True, text=True, timeout=60, check=False)
    assert result.returncode == 1, result.stdout + result.stderr
    assert "no mission ticked on /robot1/sar_tree/status within 1 s" in result.stdout
