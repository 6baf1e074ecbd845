"""``sar-tree run --record``: a real mission recorded, read back by two independent readers
(``rosbags`` and ``mcap_ros2``) with nothing skipped, and ``sar-tree replay`` drawing its
report again from the file alone."""

from __future__ import annotations

import itertools
import json
import math
import re
from pathlib import Path
from typing import Any

import pytest
from e2e.helpers import DEFAULT_TREE, FAST, REPO, read_json, run_to_end
from sar_plugins.sar.app import APP

from sar_framework.recording.recorder import RECORDED_TOPICS

pytestmark = [pytest.mark.ros, pytest.mark.slow]

REACHED = re.compile(r"^Reached (.+)\.$")


def read_with_rosbags(path: Path) -> dict[str, list[tuple[int, Any]]]:
    """Every message of the recording, deserialised by ``rosbags`` from the file's schemas
    (``AnyReader`` as its documentation shows, nothing registered by hand)."""
    from rosbags.highlevel import AnyReader

    topics: dict[str, list[tuple[int, Any]]] = {}
    with AnyReader([path]) as reader:
        for connection, stamp, raw in reader.messages():
            message = reader.deserialize(raw, connection.msgtype)
            topics.setdefault(connection.topic, []).append((stamp, message))
    return topics


def read_with_mcap_ros2(path: Path) -> dict[str, list[Any]]:
    """Every message of the recording, decoded by ``mcap_ros2`` (Foxglove's Python decoder)."""
    from mcap.reader import make_reader
    from mcap_ros2.decoder import DecoderFactory

    topics: dict[str, list[Any]] = {}
    with path.open("rb") as stream:
        reader = make_reader(stream, decoder_factories=[DecoderFactory()])
        for _schema, channel, _message, decoded in reader.iter_decoded_messages():
            topics.setdefault(channel.topic, []).append(decoded)
    return topics


def message_counts(path: Path) -> dict[str, int]:
    """Messages per topic, from the file's summary statistics."""
    from mcap.reader import make_reader

    with path.open("rb") as stream:
        summary = make_reader(stream).get_summary()
    return {summary.channels[c].topic: n
            for c, n in summary.statistics.channel_message_counts.items()}


def robot_path(tf_messages: list[tuple[int, Any]]) -> list[tuple[float, float]]:
    """The robot's positions in map: map->odom composed with odom->base_link (2D)."""
    map_odom = (0.0, 0.0, 0.0)
    path = []
    for _stamp, message in tf_messages:
        for t in message.transforms:
            q = t.transform.rotation
            yaw = math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))
            pose = (t.transform.translation.x, t.transform.translation.y, yaw)
            if (t.header.frame_id, t.child_frame_id) == ("map", "odom"):
                map_odom = pose
            elif t.header.frame_id == "odom":
                ox, oy, oyaw = map_odom
                path.append((ox + math.cos(oyaw) * pose[0] - math.sin(oyaw) * pose[1],
                             oy + math.sin(oyaw) * pose[0] + math.cos(oyaw) * pose[1]))
    return path


@pytest.fixture(scope="module")
def recorded(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, dict[str, Any]]:
    folder = tmp_path_factory.mktemp("recorded")
    record = folder / "mission.mcap"
    code, output = run_to_end([str(DEFAULT_TREE), "--speed", FAST, "--record", str(record)],
                              folder / "report")
    assert code == 0, output
    return record, read_json(folder / "report" / "mission.json")


@pytest.fixture(scope="module")
def by_rosbags(recorded) -> dict[str, list[tuple[int, Any]]]:
    """The recording decoded once by ``rosbags`` for the tests that read it."""
    return read_with_rosbags(recorded[0])


@pytest.fixture(scope="module")
def by_mcap_ros2(recorded) -> dict[str, list[Any]]:
    """The recording decoded once by ``mcap_ros2`` for the tests that read it."""
    return read_with_mcap_ros2(recorded[0])


def test_an_independent_reader_rebuilds_path_zones_and_survivors(recorded, by_rosbags) -> None:
    _record, mission = recorded
    topics = by_rosbags

    # the path: /tf, as long as the simulator's own odometer says (within 2 %)
    path = robot_path(topics["/tf"])
    length = sum(math.dist(a, b) for a, b in itertools.pairwise(path))
    assert length == pytest.approx(mission["path_length_m"], rel=0.02)
    assert math.dist(path[-1], (mission["base_station"]["x"], mission["base_station"]["y"])) \
        < 0.3

    # the zone visits: the tree status per tick, leaf verdicts "Reached <zone>."
    reached: list[tuple[str, float]] = []
    for _stamp, message in topics["/sar_tree/status"]:
        status = json.loads(message.data)
        mission_time = status["sim_s"] - status["sim_start_s"]
        for _uid, _name, _kind, node_status, text, visited in status["nodes"]:
            match = REACHED.match(text)
            if visited and node_status == "SUCCESS" and match and \
                    match.group(1) not in {r[0] for r in reached}:
                reached.append((match.group(1), mission_time))
    zones = [z for z in reached if z[0] != "base station"]
    assert [z[0] for z in zones] == [z["id"] for z in mission["zones_visited"]]
    for (_zone, sim_s), visit in zip(zones, mission["zones_visited"], strict=True):
        assert sim_s == pytest.approx(visit["arrival_sim_s"], abs=1e-3)

    # the survivors: report service requests and answers (service introspection)
    requests, acknowledged = {}, []
    for _stamp, event in topics["/report_survivor/_service_event"]:
        key = (bytes(event.info.client_gid), event.info.sequence_number)
        if event.info.event_type == 1:  # REQUEST_RECEIVED
            requests[key] = event.request[0]
        elif event.info.event_type == 2 and event.response[0].acknowledged:  # RESPONSE_SENT
            request = requests[key]
            acknowledged.append((request.survivor_id, request.location.point.x,
                                 request.location.point.y))
    expected = [(s["id"], s["x"], s["y"]) for s in mission["survivors"] if s["acknowledged"]]
    assert sorted(acknowledged) == sorted(expected)
    assert len(expected) == 2
    # ...and the frames broadcast on /tf_static, at the same places
    frames = {t.child_frame_id: (t.transform.translation.x, t.transform.translation.y)
              for _stamp, message in topics["/tf_static"] for t in message.transforms}
    for survivor_id, x, y in expected:
        assert frames[survivor_id] == pytest.approx((x, y))
    # detection requests and answers are there too, one pair per zone
    detections = [e for _s, e in topics["/detect_survivor/_service_event"]
                  if e.info.event_type == 2]
    assert len(detections) == len(mission["zones_visited"])
    assert sum(e.response[0].found for e in detections) == 2


def test_both_independent_readers_decode_every_message(recorded, by_rosbags,
                                                      by_mcap_ros2) -> None:
    record, _mission = recorded
    counts = message_counts(record)
    assert len(counts) == len(RECORDED_TOPICS) + len(APP.recorded_topics)  # the servers
    assert all(counts.values()), counts
    for topics in (by_mcap_ros2, by_rosbags):
        assert {topic: len(messages) for topic, messages in topics.items()} == counts
    # the hidden action topic, by both, with its goal ids and the robot's progress
    feedback = by_mcap_ros2["/navigate_to_pose/_action/feedback"]
    rosbags_feedback = [m for _s, m in by_rosbags["/navigate_to_pose/_action/feedback"]]
    assert [bytes(m.goal_id.uuid) for m in feedback] == \
        [bytes(m.goal_id.uuid) for m in rosbags_feedback]
    assert [m.feedback.distance_remaining for m in feedback] == \
        [m.feedback.distance_remaining for m in rosbags_feedback]
    assert any(m.feedback.distance_remaining > 0.5 for m in feedback)


def test_the_recording_is_a_rosbag2_mcap_file(recorded) -> None:
    from mcap.reader import make_reader

    record, mission = recorded
    with record.open("rb") as stream:
        reader = make_reader(stream)
        header = reader.get_header()
        summary = reader.get_summary()
        attachments = {a.name: a.data for a in reader.iter_attachments()}
    assert header.profile == "ros2"
    assert {s.encoding for s in summary.schemas.values()} == {"ros2msg"}
    assert {c.message_encoding for c in summary.channels.values()} == {"cdr"}
    counts = {summary.channels[c].topic: n
              for c, n in summary.statistics.channel_message_counts.items()}
    for topic in ("/tf", "/tf_static", "/amcl_pose", "/sar_tree/status",
                  "/navigate_to_pose/_action/status", "/navigate_to_pose/_action/feedback",
                  "/detect_survivor/_service_event", "/report_survivor/_service_event"):
        assert counts.get(topic, 0) > 0, topic
    # one status per tick, from about the first tick on
    assert counts["/sar_tree/status"] >= 0.9 * mission["ticks"]
    assert attachments["files/search_and_rescue.yaml"] == DEFAULT_TREE.read_bytes()
    assert attachments["mission_params.yaml"] == \
        (REPO / "config" / "mission_params.yaml").read_bytes()


def test_replay_draws_the_report_from_the_recording_alone(recorded, tmp_path) -> None:
    import subprocess
    import sys

    record, mission = recorded
    alone = tmp_path / "elsewhere.mcap"
    alone.write_bytes(record.read_bytes())
    result = subprocess.run([sys.executable, "-m", "sar_framework", "replay", str(alone),
                             "--report-dir", str(tmp_path / "replayed")],
                            capture_output=True, text=True, timeout=60, check=False)
    assert result.returncode == 0, result.stderr
    replayed = read_json(tmp_path / "replayed" / "mission.json")
    assert replayed["outcome"] == mission["outcome"] == "SUCCESS"
    assert replayed["zones_visited"] == [
        {**z, "arrival_wall_s": replayed["zones_visited"][i]["arrival_wall_s"]}
        for i, z in enumerate(mission["zones_visited"])]
    assert replayed["survivors"] == mission["survivors"]
    assert replayed["node_statuses"] == mission["node_statuses"]
    assert replayed["navigation_goals"] == mission["navigation_goals"]
    assert replayed["path_length_m"] == pytest.approx(mission["path_length_m"], rel=0.02)
    png = (tmp_path / "replayed" / "mission.png").read_bytes()
    assert png.startswith(b"\x89PNG")
    svg = (tmp_path / "replayed" / "tree.svg").read_text()
    assert "MissionOrReturnToBase" in svg and "NavigateToBase" in svg


def test_replay_refuses_a_file_that_is_not_a_recording(
        tmp_path, capsys: pytest.CaptureFixture[str]) -> None:
    from sar_framework.cli import main

    # sar-tree replay's main, in this process (no Python started for a refusal)
    bad = tmp_path / "not.mcap"
    bad.write_text("hello")
    assert main(["replay", str(bad)]) == 2
    said = capsys.readouterr()
    assert "not.mcap: cannot read the recording" in said.err
    assert "Traceback" not in said.out + said.err
