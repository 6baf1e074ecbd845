"""The studio's timeline: the frame at any instant of a mission, from its parts alone."""

from __future__ import annotations

import pytest
from sar_plugins.sar.events import SarKind

from sar_framework.events.event import EventKind, MissionEvent
from sar_framework.studio.timeline import PATH_STEP_M, Timeline


def status(tick: int, sim_s: float, statuses: dict[str, str], **extra) -> dict:
    nodes = [{"uid": uid, "name": f"N{uid}", "kind": "leaf", "status": s, "message": "",
              "visited": True, "depth": uid.count(".")} for uid, s in statuses.items()]
    return {"format": 1, "tree": "t", "tick": tick, "sim_s": sim_s, "status": statuses["0"],
            "complete": False, "zone": None, "nodes": nodes, "blackboard": {}, **extra}


@pytest.fixture
def timeline() -> Timeline:
    timeline = Timeline()
    timeline.add_event(MissionEvent(EventKind.STARTED, seq=1, sim_s=0.0))
    timeline.add_status(status(1, 10.0, {"0": "RUNNING", "0.0": "RUNNING"},
                               entries=[["goal", "/goal", "1", "int", "A"]],
                               entries_full=True), 100.0)
    timeline.add_pose(10.0, 0.0, 0.0, 0.0)
    timeline.add_status(status(2, 11.0, {"0": "RUNNING", "0.0": "FAILURE"}), 100.5)
    timeline.add_event(MissionEvent(EventKind.FAILURE, seq=2, sim_s=11.0, node_name="N0.0",
                                    node_uid="0.0", message="it broke"))
    timeline.add_pose(11.0, 1.0, 0.0, 0.5)
    timeline.add_status(status(3, 12.0, {"0": "SUCCESS", "0.0": "SUCCESS"},
                               entries=[["goal", "/goal", "2", "int", "A"]]), 101.0)
    timeline.add_event(MissionEvent(SarKind.SURVIVOR_BROADCAST, seq=3, sim_s=12.0,
                                    fields={"survivor_id": "s1"}, position=(1.0, 2.0, 0.0)))
    timeline.add_event(MissionEvent(SarKind.ZONE_REACHED, seq=4, sim_s=12.0,
                                    fields={"zone_id": "z"}))
    return timeline


def test_the_span_starts_at_the_first_tick_not_at_earlier_events(timeline: Timeline) -> None:
    assert timeline.start_s == 10.0
    assert timeline.end_s == 12.0


def test_a_frame_is_the_mission_as_it_was_then(timeline: Timeline) -> None:
    before = timeline.frame(10.5)
    assert before["tick"] == 1
    assert before["nodes"]["0.0"][0] == "RUNNING"
    assert before["entries"]["goal"]["value"] == "1"
    assert before["robot"] == [0.0, 0.0, 0.0]
    assert before["reasons"] == [] and before["found"] == []
    failed = timeline.frame(11.0)
    assert failed["nodes"]["0.0"][0] == "FAILURE"
    assert [r["message"] for r in failed["reasons"]] == ["it broke"]
    assert failed["robot"] == [1.0, 0.0, 0.5]
    end = timeline.frame()
    assert end["tick"] == 3 and end["status"] == "SUCCESS"
    assert end["entries"]["goal"]["value"] == "2"  # a change folded into the full list
    assert end["found"] == [{"id": "s1", "position": [1.0, 2.0, 0.0]}]  # the app's keys
    assert end["reached"] == ["z"]
    assert end["path"] == [(0.0, 0.0), (1.0, 0.0)]
    assert end["tps"] == 2.0  # two ticks in the last second of arrivals


def test_before_the_first_tick_nothing_is_known(timeline: Timeline) -> None:
    frame = timeline.frame(1.0)
    assert frame["tick"] == 0 and frame["nodes"] == {} and frame["robot"] is None


def test_marks_are_failures_and_the_apps_finds_and_arrivals(timeline: Timeline) -> None:
    assert [(m["t"], m["kind"], m["label"]) for m in timeline.marks()] == [
        (11.0, "failure", "failure N0.0"), (12.0, "found", "survivor_broadcast s1"),
        (12.0, "reached", "zone_reached z")]


def test_a_timeline_without_apps_adds_none_of_theirs(timeline: Timeline) -> None:
    bare = Timeline(apps=())
    for event in timeline.events:
        bare.add_event(event)
    assert [m["kind"] for m in bare.marks()] == ["failure"]
    assert (bare.frame()["reached"], bare.frame()["found"], bare.frame()["app_status"]) == (
        [], [], "")


def test_a_node_history_and_its_last_reason_at_an_instant(timeline: Timeline) -> None:
    detail = timeline.node_detail("0.0", 11.5)
    assert detail["history"] == [[10.0, "RUNNING"], [11.0, "FAILURE"]]
    assert detail["last_reason"]["message"] == "it broke"
    assert timeline.node_detail("0.0", 10.5)["last_reason"] is None


def test_the_path_keeps_only_poses_that_moved() -> None:
    timeline = Timeline()
    for i in range(100):
        timeline.add_pose(float(i), i * PATH_STEP_M / 10, 0.0, 0.0)
    assert len(timeline.frame()["path"]) == 10
    assert len(timeline.poses) == 100


def test_a_clock_that_runs_back_does_not_break_the_order() -> None:
    timeline = Timeline()
    timeline.add_status(status(1, 5.0, {"0": "RUNNING"}), 0.0)
    timeline.add_status(status(2, 4.0, {"0": "SUCCESS"}), 0.1)
    assert timeline.frame(5.0)["tick"] == 2


def test_the_event_list_has_every_event_in_order_with_the_instant_it_links_to() -> None:
    timeline = Timeline()
    timeline.add_event(MissionEvent(EventKind.STARTED, seq=1, sim_s=0.0, message="go"))
    timeline.add_status(status(1, 10.0, {"0": "RUNNING"}), 0.0)
    kinds = [*(k for k in EventKind if k != EventKind.STARTED), SarKind.DETECTION]
    for n, kind in enumerate(kinds):
        timeline.add_event(MissionEvent(kind, seq=n + 2, sim_s=10.0 + n / 2,
                                        node_name=f"N{n}", node_uid=f"0.{n}",
                                        fields={"zone_id": "z"} if kind == EventKind.NAVIGATION
                                        else {"survivor_id": "s"}
                                        if kind == SarKind.DETECTION else {},
                                        message=f"m{n}"))
    timeline.add_event(MissionEvent(EventKind.NOTE, seq=99, sim_s=11.0, message="late"))
    rows = timeline.event_rows()
    assert [r["kind"] for r in rows] == [k.value for k in EventKind] + ["detection", "note"]
    assert [r["seq"] for r in rows] == [1, *range(2, len(kinds) + 2), 99]
    assert [r["i"] for r in rows] == list(range(len(rows)))
    # started was stamped before the first tick: it links to the start, keeping its stamp
    assert rows[0]["t"] == 10.0 and rows[0]["sim_s"] == 0.0 and rows[0]["message"] == "go"
    assert [r["t"] for r in rows[1:-1]] == [10.0 + n / 2 for n in range(len(kinds))]
    # a stamp behind the one before it keeps the list in time order
    assert rows[-1]["t"] == rows[-2]["t"] and rows[-1]["sim_s"] == 11.0
    navigation = next(r for r in rows if r["kind"] == "navigation")
    assert (navigation["node"], navigation["uid"], navigation["fields"]) == ("N6", "0.6", ["z"])
    detection = next(r for r in rows if r["kind"] == "detection")
    assert (detection["fields"], detection["mark"]) == (["s"], "found")
    # each row's instant shows what the mission looked like then
    assert timeline.frame(navigation["t"])["tick"] == 1


def test_an_empty_timeline_lists_no_events() -> None:
    assert Timeline().event_rows() == []
