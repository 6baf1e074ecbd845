"""BroadcastSurvivorTF and the /tf_static broadcaster: every frame reaches a late subscriber."""

from __future__ import annotations

import importlib.util

import pytest
from py_trees.common import Status
from sar_plugins.sar.leaves.broadcast_survivor_tf import BroadcastSurvivorTF
from sar_testing.leaf_harness import (
    NODES,
    FixedDetector,
    TfStaticRecorder,
    spec_zone_manager,
    tree_on,
)
from sar_testing.processes import NodeProcess
from sar_testing.spin import spin_until

from sar_framework.testing import declared_leaf

pytestmark = pytest.mark.ros



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


def tf2_ros_broadcaster(node):
    tf2_ros = pytest.importorskip("tf2_ros", reason="tf2_ros is not installed here")
    return tf2_ros.StaticTransformBroadcaster(node)


def stand_in_broadcaster(node):
    from sar_framework.ros.static_tf import TopicStaticBroadcaster

    return TopicStaticBroadcaster(node)


def echo_once_qos():
    """What ``ros2 topic echo`` subscribes with to a latched topic (sensor_data, adapted)."""
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

    return QoSProfile(depth=5, reliability=ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.TRANSIENT_LOCAL)


BROADCASTERS = [stand_in_broadcaster, tf2_ros_broadcaster]


@pytest.mark.parametrize("make", BROADCASTERS, ids=["stand-in", "tf2_ros"])
def test_broadcaster_qos_is_tf2_ros(ros: tuple, make) -> None:
    """Reliability and durability as the graph shows them (depth: the test below)."""
    from rclpy.qos import DurabilityPolicy, ReliabilityPolicy

    node, _executor = ros
    make(node)
    (info,) = node.get_publishers_info_by_topic("/tf_static")
    qos = info.qos_profile
    assert (qos.reliability, qos.durability) == (ReliabilityPolicy.RELIABLE,
                                                 DurabilityPolicy.TRANSIENT_LOCAL)


@pytest.mark.parametrize("make", BROADCASTERS, ids=["stand-in", "tf2_ros"])
def test_resent_child_frame_is_ignored_and_a_late_echo_sees_every_frame(ros: tuple,
                                                                         make) -> None:
    """Depth 1: a late subscriber gets one message, with every frame, the first ``a`` kept.

    Before: the stand-in replaced ``a``, and at depth 100 a late subscriber got both past
    messages, the first holding only ``a`` (what ``ros2 topic echo --once`` printed).
    """
    from tf2_msgs.msg import TFMessage

    node, executor = ros
    recorder = TfStaticRecorder(node)
    broadcaster = make(node)
    broadcaster.sendTransform(transform("a", 1.0))
    broadcaster.sendTransform([transform("b", 2.0), transform("a", 3.0)])
    assert spin_until(executor, lambda: len(recorder.messages) == 2, 5.0)
    last = recorder.messages[-1].transforms
    assert [(t.child_frame_id, t.transform.translation.x) for t in last] == [("a", 1.0),
                                                                              ("b", 2.0)]
    late: list = []
    node.create_subscription(TFMessage, "/tf_static", late.append, echo_once_qos())
    assert spin_until(executor, lambda: bool(late), 5.0)
    spin_until(executor, lambda: False, 0.3)
    assert [[t.child_frame_id for t in m.transforms] for m in late] == [["a", "b"]]


def test_ros2_topic_echo_once_shows_every_survivor(ros: tuple) -> None:
    """The upstream CLI against our broadcaster (tf2_ros's or the stand-in, whichever is used)."""
    from sar_testing.ros2_cli import ros2_executable, run_ros2

    if ros2_executable() is None:
        pytest.skip("the ros2 command line is not installed here")
    node, _executor = ros
    detector = FixedDetector((-2.5, 3.2))
    leaf = declared_leaf(BroadcastSurvivorTF, zone_manager=spec_zone_manager(),
                               detector=detector)
    tree = tree_on(node, leaf)
    tree.tick()
    detector.pose = (4.1, -2.5)
    tree.tick()
    # DDS serves the latched message to the late joiner; no spinning needed meanwhile.
    echoed = run_ros2("topic", "echo", "/tf_static", "--once")
    assert "child_frame_id: survivor_1" in echoed
    assert "child_frame_id: survivor_2" in echoed


def test_survivor_frames_reach_a_subscriber_that_joins_later(ros: tuple, tmp_path) -> None:
    node, executor = ros
    zones = spec_zone_manager()
    detector = FixedDetector((-2.5, 3.2))
    leaf = declared_leaf(BroadcastSurvivorTF, zone_manager=zones, detector=detector)
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
    leaf = declared_leaf(BroadcastSurvivorTF, "BroadcastSurvivorTF", zone_manager=zones,
                               detector=FixedDetector(None))
    tree_on(node, leaf).tick()
    assert leaf.status == Status.FAILURE
    assert leaf.survivor_id() is None
    assert zones.next_survivor_id() == "survivor_1"
