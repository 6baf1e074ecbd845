"""The zone_coordinator node over real DDS, with a test node as the robots (no simulator).

The protocol's services and topics, the refusals with their reasons, the events file, a
robot lost when its heartbeat stops, and a bad configuration: exit 2 with one line.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import pytest
from fleet_mission import read_events, two_zone_coordinator
from sar_testing.spin import call_service, ros_node, spin_until

pytestmark = pytest.mark.ros

NAME = "/zone_coordinator/"


@pytest.mark.parametrize(("extra", "message"), [
    (["-p", "bid_window_wall_s:=-1.0"], "parameters: bid_window_wall_s: must be > 0, got -1.0"),
    (["-p", "robot_timeout_wall_s:=0.0"], "parameters: robot_timeout_wall_s: must be > 0"),
    (["-p", "events_file:=/nonexistent/dir/e.jsonl"], "events_file: cannot open "
     "/nonexistent/dir/e.jsonl"),
    (["-p", "zones.zone_b.x:=nan"], "zones.zone_b.x: must be finite"),
    (["-p", "start_wait_wall_s:=-1.0"], "parameters: start_wait_wall_s: must be >= 0"),
    (["-p", "robots:=[r1, r1]"], "robots[1]: r1 is listed twice"),
])
def test_a_bad_configuration_exits_2_with_one_clear_line(tmp_path: Path, extra: list[str],
                                                        message: str) -> None:
    proc = two_zone_coordinator(tmp_path, *extra).start()
    try:
        assert proc.wait(timeout=20.0) == 2
    finally:
        proc.stop()
    assert message in proc.output
    assert "Traceback" not in proc.output


def test_the_protocol_its_refusals_and_a_lost_robot(tmp_path: Path) -> None:
    from sar_fleet_interfaces.msg import FleetHeartbeat, ZoneAward, ZoneNotice
    from sar_fleet_interfaces.srv import BidZones, FinishZone, RegisterSurvivor, RequestZone

    from sar_framework.ros.qos import latched_qos

    events_file = tmp_path / "events.jsonl"
    with two_zone_coordinator(tmp_path, "-p", f"events_file:={events_file}", "-p",
                     "robot_timeout_wall_s:=1.0", "-p", "bid_window_wall_s:=1.0") as proc, \
            ros_node("fake_robots") as (node, executor):
        proc.wait_for_output("ready", timeout=20.0)
        notices: list[Any] = []
        awards: list[Any] = []
        node.create_subscription(ZoneNotice, NAME + "notices", notices.append, latched_qos(100))
        node.create_subscription(ZoneAward, NAME + "awards", awards.append, latched_qos(100))
        beat = node.create_publisher(FleetHeartbeat, NAME + "heartbeat", 10)
        alive = {"r1": True, "r2": False}  # r2 runs from after the first award on

        def heartbeats() -> None:
            for robot, on in alive.items():
                if on:
                    beat.publish(FleetHeartbeat(robot=robot))

        node.create_timer(0.2, heartbeats)

        def call(srv: Any, service: str, **fields: Any) -> Any:
            return call_service(node, executor, srv, NAME + service, srv.Request(**fields))

        assert call(RequestZone, "request_zone", robot="r1").accepted
        assert spin_until(executor, lambda: bool(notices), 10.0)
        notice = notices[-1]
        assert (list(notice.zone_ids), list(notice.robots)) == (["zone_a", "zone_b"], ["r1"])
        refused = call(BidZones, "bid_zones", auction_id=notice.auction_id, robot="r1",
                       zone_ids=["zone_a"], costs=[1.0, 2.0])
        assert (refused.accepted, refused.reason) == (False, "1 zone ids but 2 costs")
        refused = call(BidZones, "bid_zones", auction_id=99, robot="r1",
                       zone_ids=["zone_a"], costs=[1.0])
        assert refused.reason.startswith("auction 99 is not open")
        assert call(BidZones, "bid_zones", auction_id=notice.auction_id, robot="r1",
                    zone_ids=["zone_a", "zone_b"], costs=[4.0, math.inf]).accepted
        assert spin_until(executor, lambda: bool(awards), 10.0)
        assert (awards[-1].robot, awards[-1].zone_id, awards[-1].cost) == ("r1", "zone_a", 4.0)
        alive["r2"] = True

        refused = call(FinishZone, "finish_zone", robot="r1", zone_id="zone_b", outcome=0)
        assert refused.reason == "r1 does not hold zone_b (it is open)"
        refused = call(FinishZone, "finish_zone", robot="r1", zone_id="zone_a", outcome=7)
        assert refused.reason.startswith("unknown outcome 7")
        assert call(FinishZone, "finish_zone", robot="r1", zone_id="zone_a", outcome=0).accepted

        # r2 wins zone_b, then falls silent: lost, and zone_b goes back to auction.
        assert call(RequestZone, "request_zone", robot="r2").accepted
        assert spin_until(executor, lambda: notices[-1].robots == ["r2"], 10.0)
        assert call(BidZones, "bid_zones", auction_id=notices[-1].auction_id, robot="r2",
                    zone_ids=["zone_b"], costs=[3.0]).accepted
        assert spin_until(executor, lambda: awards[-1].robot == "r2", 10.0)
        found = call(RegisterSurvivor, "register_survivor", robot="r2", zone_id="zone_b",
                     x=3.5, y=3.2)
        assert (found.survivor_id, found.report) == ("survivor_1", True)
        alive["r2"] = False
        # robot_timeout_wall_s is 1 s; the 10 s of spin_until are only an outer safety bound.
        assert spin_until(executor, lambda: any(
            e["kind"] == "robot_lost" for e in read_events(events_file)), 10.0)
        alive["r2"] = True  # heard again: back, idle, holding nothing
        assert spin_until(executor, lambda: any(
            e["message"] == "r2 rejoined the fleet (it was lost)"
            for e in read_events(events_file)), 10.0)
        assert call(RequestZone, "request_zone", robot="r1").accepted
        assert spin_until(executor, lambda: notices[-1].robots == ["r1"]
                          and list(notices[-1].zone_ids) == ["zone_b"], 10.0)
        assert call(BidZones, "bid_zones", auction_id=notices[-1].auction_id, robot="r1",
                    zone_ids=["zone_b"], costs=[6.0]).accepted
        assert spin_until(executor, lambda: awards[-1].robot == "r1", 10.0)
        again = call(RegisterSurvivor, "register_survivor", robot="r1", zone_id="zone_b",
                     x=3.7, y=3.0)  # the lost robot's survivor, 0.3 m off: r1 reports it
        assert (again.survivor_id, again.report, again.found_by) == ("survivor_1", True, "r2")
        assert call(FinishZone, "finish_zone", robot="r1", zone_id="zone_b", outcome=0).accepted
        done = call(RequestZone, "request_zone", robot="r1")
        assert (done.accepted, done.done) == (False, True)
        assert spin_until(executor, lambda: read_events(events_file)[-1]["kind"] == "complete",
                          5.0)
    kinds = [e["kind"] for e in read_events(events_file)]
    assert kinds.count("searched") == 2 and kinds.count("award") == 3
    lost = next(e for e in read_events(events_file) if e["kind"] == "robot_lost")
    assert (lost["robot"], lost["zone_ids"]) == ("r2", ["zone_b"])
    assert "the next finder of survivor_1 reports it" in lost["message"]
    registered = [e for e in read_events(events_file) if e["kind"] == "survivor_registered"]
    assert [(e["robot"], e["survivor_id"], e["zone_id"]) for e in registered] == [
        ("r2", "survivor_1", "zone_b"), ("r1", "survivor_1", "zone_b")]
    assert registered[0]["position"][:2] == [3.5, 3.2]
    bid = next(e for e in read_events(events_file) if e["kind"] == "bid")
    assert bid["costs"] == [4.0, None]  # inf is null in JSON


def test_the_first_round_waits_for_every_robot_of_the_fleet(tmp_path: Path) -> None:
    from sar_fleet_interfaces.msg import ZoneNotice
    from sar_fleet_interfaces.srv import RequestZone

    from sar_framework.ros.qos import latched_qos

    events_file = tmp_path / "events.jsonl"
    # start_wait_wall_s is an outer safety bound here: the round must open on r2's request.
    with two_zone_coordinator(tmp_path, "-p", f"events_file:={events_file}",
                              "-p", "robots:=[r1, r2]", "-p", "start_wait_wall_s:=120.0"
                              ) as proc, ros_node("fake_robots") as (node, executor):
        proc.wait_for_output("ready", timeout=20.0)
        assert "waits up to 120 s for r1, r2" in proc.output
        notices: list[Any] = []
        node.create_subscription(ZoneNotice, NAME + "notices", notices.append, latched_qos(100))
        for robot in ("r1", "r2"):
            assert call_service(node, executor, RequestZone, NAME + "request_zone",
                                RequestZone.Request(robot=robot)).accepted
        assert spin_until(executor, lambda: bool(notices), 10.0)
    # r1 asked first: a round opened then would have named r1 alone.
    assert list(notices[0].robots) == ["r1", "r2"]
    first = next(e for e in read_events(events_file) if e["kind"] == "auction")
    assert (first["auction_id"], first["robots"]) == (1, ["r1", "r2"])
