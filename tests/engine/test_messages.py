"""Message fields from the installed .msg files, and literals checked against them."""

from __future__ import annotations

import pytest

from sar_framework.engine.messages import MessageNotFoundError, literal_problems, message_fields

# Message literals are read from the installed ROS interfaces' .msg files: not in the
# engine's py_trees-only environment (.venv-compat), where ROS tests are skipped.
pytestmark = pytest.mark.ros


def test_fields_come_from_the_msg_files() -> None:
    assert message_fields("geometry_msgs/msg/PoseStamped") == {
        "header": "std_msgs/msg/Header", "pose": "geometry_msgs/msg/Pose"}
    assert message_fields("geometry_msgs/msg/Point") == {"x": "float64", "y": "float64",
                                                         "z": "float64"}
    assert message_fields("nav_msgs/msg/Path")["poses"] == "geometry_msgs/msg/PoseStamped[]"


def test_a_literal_of_the_messages_own_fields_fits() -> None:
    assert literal_problems("geometry_msgs/msg/PoseStamped", {
        "header": {"frame_id": "map"},
        "pose": {"position": {"x": 1, "y": 2.5}, "orientation": {"w": 1.0}}}) == []


def test_a_wrong_field_gets_a_did_you_mean_and_its_path() -> None:
    assert literal_problems("geometry_msgs/msg/PoseStamped",
                            {"pose": {"postion": {"x": 1.0}}}) == [
        "pose.postion: not a field of geometry_msgs/msg/Pose (did you mean 'position'?) "
        "(fields: position, orientation)"]


def test_a_wrong_value_type_is_named() -> None:
    assert literal_problems("geometry_msgs/msg/Pose",
                            {"position": {"x": 1.0, "z": "up"}, "orientation": 3}) == [
        "position.z: expected a float64, got 'up'",
        "orientation: a geometry_msgs/msg/Quaternion is written as a mapping of its fields "
        "(x, y, z, w), got 3"]
    assert literal_problems("nav_msgs/msg/Path", {"poses": [{"pose": {"position": {}}},
                                                            {"pose": {"positon": {}}}]}) == [
        "poses[1].pose.positon: not a field of geometry_msgs/msg/Pose (did you mean "
        "'position'?) (fields: position, orientation)"]


def test_an_uninstalled_type_is_said_so() -> None:
    with pytest.raises(MessageNotFoundError, match=r"no installed \.msg file defines nope_msgs"):
        message_fields("nope_msgs/msg/Nothing")
