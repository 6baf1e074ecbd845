"""Message literals: the message's fields, the pose shorthand and Nav2's text forms."""

from __future__ import annotations

import math

import pytest

from sar_framework.engine.message_literals import (
    LiteralError,
    MessageLiteral,
    message_literal,
    message_text,
)

POSE = "geometry_msgs/msg/PoseStamped"

# Message literals are read from the installed ROS interfaces' .msg files: not in the
# engine's py_trees-only environment (.venv-compat), where ROS tests are skipped.
pytestmark = pytest.mark.ros


def test_the_pose_shorthand_fills_frame_and_stamp() -> None:
    goal = message_literal(POSE, {"x": 1, "y": 2.0, "yaw": math.pi / 2})
    assert goal.fields["header"] == {"frame_id": "map", "stamp": "now"}
    assert goal.fields["pose"]["position"] == {"x": 1.0, "y": 2.0, "z": 0.0}
    orientation = goal.fields["pose"]["orientation"]
    assert orientation["z"] == pytest.approx(math.sqrt(0.5))
    assert orientation["w"] == pytest.approx(math.sqrt(0.5))
    assert message_literal(POSE, {"x": 1, "frame_id": "odom"}).fields["header"]["frame_id"] == (
        "odom")


def test_the_shorthand_for_other_pose_types() -> None:
    assert message_literal("geometry_msgs/msg/Pose2D", {"x": 1, "y": 2, "yaw": 0.5}).fields == {
        "x": 1.0, "y": 2.0, "theta": 0.5}
    covariance = message_literal("geometry_msgs/msg/PoseWithCovarianceStamped", "1;2;0")
    assert covariance.fields["pose"]["pose"]["position"]["x"] == 1.0
    assert covariance.fields["header"]["frame_id"] == "map"
    assert "header" not in message_literal("geometry_msgs/msg/Pose", {"x": 1}).fields


def test_nav2s_text_forms() -> None:
    goal = message_literal(POSE, "1500000000;odom;1;2;0;0;0;0;1")
    assert goal.fields["header"] == {"stamp": {"sec": 1, "nanosec": 500000000},
                                     "frame_id": "odom"}
    assert goal.fields["pose"]["orientation"] == {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0}
    assert message_literal(POSE, "1.0;2.0;0.0").fields["pose"]["position"]["y"] == 2.0
    assert message_literal("geometry_msgs/msg/Quaternion", "0;0;0;1") == MessageLiteral(
        "geometry_msgs/msg/Quaternion", {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0})


def test_a_full_literal_keeps_what_it_gives() -> None:
    goal = message_literal(POSE, {"header": {"stamp": {"sec": 3}}, "pose": {}})
    assert goal.fields["header"] == {"stamp": {"sec": 3}, "frame_id": "map"}
    assert message_literal(POSE, {"header": {"stamp": "now"}}).fields["header"]["stamp"] == "now"


@pytest.mark.parametrize(
    ("type_", "value", "message"),
    [
        (POSE, {"x": 1, "pose": {}}, "write either the fields of geometry_msgs/msg/PoseStamped "
                                     "(pose) or the pose shorthand (x), not both"),
        (POSE, {"yew": 1}, "yew: neither a field of geometry_msgs/msg/PoseStamped (header, "
                           "pose) nor a key of its pose shorthand (x, y, z, yaw, frame_id) (did "
                           "you mean 'yaw'?)"),
        (POSE, {"x": "one"}, "x: expected a number, got 'one'"),
        (POSE, "1;2", "'1;2' is not a geometry_msgs/msg/PoseStamped: expected "
                      "'stamp_ns;frame_id;x;y;z;qx;qy;qz;qw' or 'x;y;yaw'"),
        (POSE, "now;map;1;2;0;0;0;0;1", "the stamp is in integer nanoseconds, got 'now'"),
        (POSE, "a;b;c", "'a;b;c' (x;y;yaw): expected numbers"),
        ("geometry_msgs/msg/Pose", {"x": 1, "frame_id": "map"}, "frame_id: not a key of the "
                                                               "pose shorthand"),
        ("nav_msgs/msg/Path", "1;2", "a nav_msgs/msg/Path has no text form"),
        (POSE, {"goal": None}, "quote it: '\"{goal}\"'"),
        ("nope_msgs/msg/Nothing", {}, "no installed .msg file defines nope_msgs/msg/Nothing"),
    ],
)
def test_what_does_not_fit_is_said(type_: str, value: object, message: str) -> None:
    with pytest.raises(LiteralError) as error:
        message_literal(type_, value)
    assert message in str(error.value)


def test_the_text_bt_cpp_reads() -> None:
    assert message_text(message_literal(POSE, {"header": {"frame_id": "odom", "stamp": {
        "sec": 2, "nanosec": 5}}, "pose": {"position": {"x": 1}}})) == (
        "2000000005;odom;1.0;0.0;0.0;0.0;0.0;0.0;1.0")
    assert message_text(message_literal(POSE, "1;2;0")).startswith("0;map;1.0;2.0;")
    assert message_text(message_literal("geometry_msgs/msg/Point", {"y": 2})) == "0.0;2.0;0.0"
    assert message_text(message_literal("geometry_msgs/msg/Pose2D", {"x": 1, "y": 2})) == (
        'json:{"x":1,"y":2}')


def test_a_pose_literal_reads_compactly() -> None:
    assert str(message_literal(POSE, {"x": 1, "y": 2, "yaw": math.pi / 2})) == (
        "PoseStamped(x=1, y=2, yaw=1.57)")
    assert str(message_literal(POSE, "0;odom;1;2;0;0;0;0;1")) == "PoseStamped@odom(x=1, y=2, yaw=0)"
    assert str(message_literal("geometry_msgs/msg/Point", "1;2;3")) == (
        "Point{'x': 1.0, 'y': 2.0, 'z': 3.0}")
