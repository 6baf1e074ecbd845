"""Schemas and the MCAP writer: rclpy's CDR bytes, decoded by rosbags and mcap_ros2 from our
definitions."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from sar_framework.recording.bag_writer import BagWriter
from sar_framework.recording.msgdefs import DefinitionError, message_definition, schema_name

pytestmark = pytest.mark.ros


def decode(type_name: str, data: bytes) -> list[Any]:
    """Deserialise ``data`` as stored, by a rosbags typestore that knows only the stored
    definition and by mcap_ros2's decoder made from the same text."""
    from mcap_ros2._dynamic import generate_dynamic
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    name, definition = schema_name(type_name), message_definition(type_name)
    store = get_typestore(Stores.EMPTY)
    store.register(get_types_from_msg(definition, name))
    return [store.deserialize_cdr(data, name), generate_dynamic(name, definition)[name](data)]


def test_service_event_and_action_feedback_are_stored_under_msg_names() -> None:
    assert schema_name("sar_interfaces/srv/ReportSurvivor_Event") == \
        "sar_interfaces/msg/ReportSurvivorEvent"
    assert schema_name("nav2_msgs/action/NavigateToPose_FeedbackMessage") == \
        "nav2_msgs/msg/NavigateToPoseFeedbackMessage"
    assert schema_name("tf2_msgs/msg/TFMessage") == "tf2_msgs/msg/TFMessage"


def test_tf_definition_lists_each_dependency_once() -> None:
    text = message_definition("tf2_msgs/msg/TFMessage")
    headers = [line for line in text.splitlines() if line.startswith("MSG: ")]
    assert sorted(headers) == ["MSG: builtin_interfaces/Time", "MSG: geometry_msgs/Quaternion",
                               "MSG: geometry_msgs/Transform",
                               "MSG: geometry_msgs/TransformStamped",
                               "MSG: geometry_msgs/Vector3", "MSG: std_msgs/Header"]
    assert "geometry_msgs/TransformStamped[] transforms" in text.split("=" * 80)[0]


def test_service_event_round_trip() -> None:
    from rclpy.serialization import serialize_message
    from sar_interfaces.srv import ReportSurvivor

    event = ReportSurvivor.Event()
    request = ReportSurvivor.Request(survivor_id="survivor_7")
    request.location.header.frame_id = "map"
    request.location.point.x, request.location.point.y = 1.5, -2.25
    event.request = [request]
    event.info.event_type = 1
    event.info.sequence_number = 42
    type_name = "sar_interfaces/srv/ReportSurvivor_Event"
    for decoded in decode(type_name, serialize_message(event)):
        assert decoded.info.sequence_number == 42
        assert decoded.request[0].survivor_id == "survivor_7"
        assert (decoded.request[0].location.point.x, decoded.request[0].location.point.y) == \
            (1.5, -2.25)
        assert len(decoded.response) == 0


def test_action_feedback_round_trip() -> None:
    from nav2_msgs.action import NavigateToPose
    from rclpy.serialization import serialize_message

    message = NavigateToPose.Impl.FeedbackMessage()
    message.goal_id.uuid = list(range(16))
    message.feedback.distance_remaining = 3.5
    message.feedback.current_pose.pose.position.x = -1.0
    type_name = "nav2_msgs/action/NavigateToPose_FeedbackMessage"
    for decoded in decode(type_name, serialize_message(message)):
        assert list(decoded.goal_id.uuid) == list(range(16))
        assert decoded.feedback.distance_remaining == 3.5
        assert decoded.feedback.current_pose.pose.position.x == -1.0


def test_a_type_that_is_not_installed_is_named() -> None:
    with pytest.raises(DefinitionError, match=r"no_such_msgs/msg/Thing\.msg is not installed"):
        message_definition("no_such_msgs/msg/Thing")


def test_writer_output_opens_in_rosbags(tmp_path: Path) -> None:
    from geometry_msgs.msg import PoseWithCovarianceStamped
    from rclpy.serialization import serialize_message
    from rosbags.highlevel import AnyReader

    path = tmp_path / "out.mcap"
    writer = BagWriter(path)
    writer.add_topic("/amcl_pose", "geometry_msgs/msg/PoseWithCovarianceStamped")
    for i in range(3):
        pose = PoseWithCovarianceStamped()
        pose.pose.pose.position.x = float(i)
        writer.write("/amcl_pose", serialize_message(pose), log_time_ns=1_000 + i)
    writer.attach("notes.txt", b"hello")
    writer.close()
    writer.close()  # idempotent
    with AnyReader([path]) as reader:
        values = [reader.deserialize(raw, c.msgtype).pose.pose.position.x
                  for c, _t, raw in reader.messages()]
        assert [c.topic for c in reader.connections] == ["/amcl_pose"]
    assert values == [0.0, 1.0, 2.0]


def test_recorder_names_an_output_it_cannot_write(tmp_path: Path) -> None:
    import subprocess
    import sys

    blocker = tmp_path / "a_file"
    blocker.write_text("")
    target = blocker / "mission.mcap"  # a folder that is a file
    result = subprocess.run([sys.executable, "-m", "sar_framework.recording", "--ros-args",
                             "-p", f"output:={target}"], capture_output=True, text=True,
                            timeout=60, check=False)
    assert result.returncode == 2
    assert f"cannot write the recording '{target}'" in result.stdout + result.stderr
    assert "Traceback" not in result.stdout + result.stderr


def test_every_recorded_type_decodes_with_mcap_ros2_and_rosbags(tmp_path: Path) -> None:
    """One message of each recorded topic, written as the recorder writes it, decodes with
    both independent readers (``mcap_ros2`` refused ``..._FeedbackMessage`` once)."""
    from mcap.reader import make_reader
    from mcap_ros2.decoder import DecoderFactory
    from rclpy.serialization import serialize_message
    from rosbags.highlevel import AnyReader
    from sar_plugins.sar.app import APP

    from sar_framework.recording.recorder import RECORDED_TOPICS, RecordedTopic, message_class

    every = (*RECORDED_TOPICS, *(RecordedTopic(*topic) for topic in APP.recorded_topics))

    path = tmp_path / "all.mcap"
    writer = BagWriter(path)
    for topic in every:
        writer.add_topic(topic.name, topic.type_name)
        writer.write(topic.name, serialize_message(message_class(topic.type_name)()))
    writer.close()
    with path.open("rb") as stream:
        decoded = [channel.topic for _schema, channel, _message, _decoded in
                   make_reader(stream, decoder_factories=[DecoderFactory()])
                   .iter_decoded_messages()]
    assert sorted(decoded) == sorted(t.name for t in every)
    with AnyReader([path]) as reader:
        topics = [c.topic for c, _t, raw in reader.messages()
                  if reader.deserialize(raw, c.msgtype) is not None]
    assert sorted(topics) == sorted(t.name for t in every)
