"""BroadcastSurvivorTF and the /tf_static broadcaster: every frame reaches a late subscriber."""

from __future__ import annotations

import importlib.util
from dataclasses import dataclass

import pytest
from py_trees.common import Status
from sar_plugins.broadcast_survivor_tf import BroadcastSurvivorTF
from sar_testing.leaf_harness import NODES, TfStaticRecorder, spec_zone_manager, tree_on
from sar_testing.processes import NodeProcess
from sar_testing.spin import spin_until

pytestmark = pytest.mark.ros


@dataclass
class FixedDetector:
    """Stands in for DetectSurvivor: a settable detection result."""

    pose: tuple[float, float] | None = None

    def was_found(self) -> bool:
        return self.pose is not None

    def survivor_pose(self) -> tuple[float, float] | None:
        return self.pose


def transform(child: str, x: float):
    from geometry_msgs.msg import TransformStamped

    t = TransformStamped()
    t.header.frame_id = "map"
    t.child_frame_id = child
    t.transform.translation.x = x
    t.transform.rotation.w = 1.0
    return t


def test_make_static_broadcaster_uses_tf2_ros_only_when_importable(ros: tuple) -> None:
    from sar_framework.ros.static_tf import TopicStaticBroadcaster, make_static_broadcaster

    node, _executor = ros
    broadcaster = make_static_broadcaster(node)
    has_tf2_ros = importlib.util.find_spec("tf2_ros") is not None
    assert isinstance(broadcaster, TopicStaticBroadcaster) is not has_tf2_ros


def test_stand_in_resends_every_frame_and_replaces_by_child(ros: tuple) -> None:
    from sar_framework.ros.static_tf import TopicStaticBroadcaster

    node, executor = ros
    recorder = TfStaticRecorder(node)
    broadcaster = TopicStaticBroadcaster(node)
    broadcaster.sendTransform(transform("a", 1.0))
    broadcaster.sendTransform([transform("b", 2.0), transform("a", 3.0)])
    assert spin_until(executor, lambda: len(recorder.messages) == 2, 5.0)
    last = recorder.messages[-1].transforms
    assert [(t.child_frame_id, t.transform.translation.x) for t in last] == [("a", 3.0),
                                                                              ("b", 2.0)]
    assert broadcaster.frames() == ["a", "b"]


def test_survivor_frames_reach_a_subscriber_that_joins_later(ros: tuple, tmp_path) -> None:
    node, executor = ros
    zones = spec_zone_manager()
    detector = FixedDetector((-2.5, 3.2))
    leaf = BroadcastSurvivorTF("BroadcastSurvivorTF", zone_manager=zones, detector=detector)
    tree = tree_on(node, leaf)
    tree.tick()
    assert leaf.status == Status.SUCCESS
    assert leaf.survivor_id() == "survivor_1"
    detector.pose = (4.1, -2.5)
    tree.tick()  # a fresh activation: allocates the next id
    assert leaf.status == Status.SUCCESS
    assert leaf.survivor_id() == "survivor_2"
    assert leaf.feedback_message == "Broadcast static TF map -> survivor_2 at (4.10, -2.50)."

    with NodeProcess([str(NODES / "tf_static_echo.py")], "tf_echo", log_dir=tmp_path) as echo:
        echo.wait_for_output("listening")
        # The newest message carries both frames, as tf2_ros's broadcaster does.
        echo.wait_for_output(r"tf_static: map->survivor_1,map->survivor_2", timeout=15.0)
    spin_until(executor, lambda: False, 0.1)


def test_no_survivor_fails_without_allocating(ros: tuple) -> None:
    node, _executor = ros
    zones = spec_zone_manager()
    leaf = BroadcastSurvivorTF("BroadcastSurvivorTF", zone_manager=zones,
                               detector=FixedDetector(None))
    tree_on(node, leaf).tick()
    assert leaf.status == Status.FAILURE
    assert leaf.survivor_id() is None
    assert zones.next_survivor_id() == "survivor_1"
