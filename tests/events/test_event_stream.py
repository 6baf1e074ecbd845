"""The event stream's contract: encoding, the JSON-lines file, the emitter, the ROS message."""

from __future__ import annotations

import json
from pathlib import Path

import py_trees
import pytest
from sar_plugins.sar.events import SarKind
from sar_plugins.sar.zone_manager import ZoneManager

from sar_framework.events.emitter import NO_EVENTS, EventEmitter, events_from
from sar_framework.events.event import (
    EventFormatError,
    EventKind,
    MissionEvent,
    event_from_dict,
    event_from_json,
)
from sar_framework.events.jsonl import (
    EventFileFollower,
    EventFileWriter,
    JsonLinesFollower,
    read_events,
)

REPO = Path(__file__).resolve().parents[2]
MSG = REPO / "interfaces" / "sar_interfaces" / "msg" / "MissionEvent.msg"

FULL = MissionEvent(SarKind.SURVIVOR_BROADCAST, seq=7, sim_s=21.4, wall_s=2.125,
                    node_name="BroadcastSurvivorTF", node_uid="0.0.3.0.1",
                    node_kind="BroadcastSurvivorTF", status="", message="é ünïcode, \"quoted\"",
                    position=(-2.5, 3.2, 0.0),
                    fields={"zone_id": "zone_a", "survivor_id": "survivor_1"})


@pytest.mark.parametrize("kind", list(EventKind))
def test_every_kind_survives_a_json_round_trip(kind: EventKind) -> None:
    event = MissionEvent(kind, seq=3, sim_s=1.5, wall_s=0.25, message=f"{kind.value} said")
    line = event.to_json()
    assert "\n" not in line
    assert json.loads(line)["kind"] == kind.value
    assert event_from_json(line) == event


def test_a_full_event_round_trips_with_its_position_and_text() -> None:
    assert event_from_json(FULL.to_json()) == FULL
    assert json.loads(FULL.to_json())["position"] == [-2.5, 3.2, 0.0]


def test_the_python_kinds_are_the_message_constants() -> None:
    """events/event.py and MissionEvent.msg name the same kinds (no second list drifts)."""
    constants = {}
    for line in MSG.read_text().splitlines():
        if line.startswith("string KIND_"):
            name, value = line.split("#")[0].split(" ", 1)[1].split("=")
            constants[name.strip()] = value.strip()
    assert constants == {f"KIND_{k.name}": k.value for k in EventKind}


@pytest.mark.parametrize(("document", "words"), [
    ([1, 2], "JSON object"),
    ({"kind": "Teleported!"}, "unknown kind"),
    ({"kind": 3}, "unknown kind"),
    ({"kind": "status", "fields": {"zone_id": 3}}, "fields"),
    ({"kind": "status", "fields": ["zone_id"]}, "fields"),
    ({"kind": "status", "seq": -1}, "seq"),
    ({"kind": "status", "seq": True}, "seq"),
    ({"kind": "status", "sim_s": "soon"}, "sim_s"),
    ({"kind": "status", "sim_s": float("nan")}, "sim_s"),
    ({"kind": "status", "message": 3}, "message"),
    ({"kind": "status", "position": [1.0, 2.0]}, "position"),
    ({"kind": "status", "colour": "red"}, "unknown field"),
])
def test_bad_documents_are_refused_with_the_field_named(document: object, words: str) -> None:
    with pytest.raises(EventFormatError, match=words):
        event_from_dict(document)


def test_an_apps_kind_and_fields_need_no_change_of_the_event() -> None:
    event = MissionEvent("shelf_scanned", seq=4, sim_s=3.5, fields={"shelf": "nw", "items": "12"})
    assert event_from_json(event.to_json()) == event
    assert event.value("shelf") == "nw" and event.value("zone_id") == ""
    assert json.loads(event.to_json())["kind"] == "shelf_scanned"


@pytest.mark.ros
def test_an_apps_kind_and_fields_travel_in_the_message_as_key_value_pairs() -> None:
    from sar_framework.runner.event_topic import from_message, to_message

    event = MissionEvent("shelf_scanned", seq=4, sim_s=3.5, fields={"shelf": "nw", "items": "12"})
    message = to_message(event)
    assert [(pair.key, pair.value) for pair in message.fields] == [("shelf", "nw"),
                                                                   ("items", "12")]
    assert from_message(message) == event


def test_not_json_is_refused() -> None:
    with pytest.raises(EventFormatError, match="not JSON"):
        event_from_json("{torn")


def test_the_file_is_written_a_line_per_event_and_read_back(tmp_path: Path) -> None:
    path = tmp_path / "out" / "events.jsonl"
    writer = EventFileWriter(path)
    events = [MissionEvent(EventKind.STARTED, seq=1), FULL.numbered(2)]
    for event in events:
        writer(event)
    assert len(path.read_text(encoding="utf-8").splitlines()) == 2  # flushed at once
    writer.close()
    writer(MissionEvent(EventKind.VERDICT))  # after close: ignored
    assert read_events(path) == events
    appended = EventFileWriter(path, append=True)
    appended(MissionEvent(EventKind.VERDICT, seq=3, status="SUCCESS"))
    appended.close()
    assert [e.kind for e in read_events(path)] == [EventKind.STARTED,
                                                    SarKind.SURVIVOR_BROADCAST,
                                                    EventKind.VERDICT]


def test_the_follower_reads_only_complete_lines_and_skips_bad_ones(tmp_path: Path) -> None:
    path = tmp_path / "events.jsonl"
    follower = EventFileFollower(path)
    assert follower.poll() == []  # no file yet: nothing happened yet
    line = FULL.to_json()
    with path.open("w", encoding="utf-8") as handle:
        handle.write(line[:20])
        handle.flush()
        assert follower.poll() == []  # half a line is not an event
        handle.write(line[20:] + "\nnot json\n" + '{"kind": "Warp!"}\n')
        handle.flush()
        assert follower.poll() == [FULL]
        assert follower.rejected == 2
        assert follower.poll() == []
        handle.write(MissionEvent(EventKind.VERDICT, seq=8).to_json() + "\n")
    assert [e.kind for e in follower.poll()] == [EventKind.VERDICT]


def test_a_json_lines_follower_reads_any_value(tmp_path: Path) -> None:
    path = tmp_path / "trace.jsonl"
    path.write_text('{"event": "accepted"}\n{"event": "canc')
    follower = JsonLinesFollower(path)
    assert follower.poll() == [{"event": "accepted"}]
    with path.open("a") as handle:
        handle.write('eled"}\n')
    assert follower.poll() == [{"event": "canceled"}]


def test_the_emitter_numbers_stamps_names_and_fans_out() -> None:
    leaf = py_trees.behaviours.Success(name="Leafy")
    got: list[MissionEvent] = []
    clock = iter([10.0, 10.5])
    emitter = EventEmitter([got.append], sim_now=lambda: next(clock),
                           nodes={"0.2": (leaf, "Success")})
    first = emitter.emit(EventKind.STATUS, source=leaf, status="SUCCESS", message="ok")
    second = emitter.emit(SarKind.SURVIVOR_BROADCAST, survivor_id="survivor_1",
                          position=(1.0, 2.0))
    assert got == [first, second] == emitter.emitted
    assert (first.seq, first.sim_s, first.node_name, first.node_uid, first.node_kind) == (
        1, 10.0, "Leafy", "0.2", "Success")
    assert (second.seq, second.sim_s, second.node_uid, second.position) == (
        2, 10.5, "", (1.0, 2.0, 0.0))


def test_a_behaviour_set_up_without_an_emitter_gets_one_that_drops_events() -> None:
    assert events_from({}) is NO_EVENTS
    assert events_from({"events": "not an emitter"}) is NO_EVENTS
    NO_EVENTS.emit(EventKind.NOTE, message="nobody listens")
    assert NO_EVENTS.emitted == []
    emitter = EventEmitter()
    assert events_from({"events": emitter}) is emitter


def test_the_zone_manager_tells_reached_and_unreached_zones() -> None:
    zones = [{"id": z, "x": float(i), "y": 0.0, "yaw": 0.0}
             for i, z in enumerate(("zone_a", "zone_b", "zone_c"))]
    manager = ZoneManager(zones, {"x": 0.0, "y": 0.0, "yaw": 0.0})
    told: list[tuple[EventKind, str]] = []
    manager.observe(lambda kind, zone: told.append((kind, zone["id"])))
    manager.mark_reached("zone_a")
    manager.advance()
    manager.advance()  # zone_b never reached
    manager.mark_reached("zone_c")
    manager.advance()
    manager.advance()  # past the end: nothing more to tell
    assert told == [(SarKind.ZONE_REACHED, "zone_a"), (SarKind.ZONE_UNREACHED, "zone_b"),
                    (SarKind.ZONE_REACHED, "zone_c")]


@pytest.mark.ros
def test_the_ros_message_carries_every_field() -> None:
    from sar_framework.runner.event_topic import event_qos, from_message, to_message

    message = to_message(FULL)
    assert (message.stamp.sec, message.stamp.nanosec) == (21, 400_000_000)
    assert message.kind == "survivor_broadcast" and message.has_position
    assert from_message(message) == FULL
    bare = MissionEvent(EventKind.COMPLETION, seq=9, sim_s=0.001, status="FAILURE")
    assert not to_message(bare).has_position
    assert from_message(to_message(bare)) == bare
    message.kind = "Teleported!"
    with pytest.raises(ValueError, match="Teleported!"):
        from_message(message)
    from rclpy.qos import DurabilityPolicy, ReliabilityPolicy

    qos = event_qos()
    assert (qos.reliability, qos.durability, qos.depth) == (
        ReliabilityPolicy.RELIABLE, DurabilityPolicy.TRANSIENT_LOCAL, 1000)
