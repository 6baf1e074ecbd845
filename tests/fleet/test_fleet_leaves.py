"""ClaimZone, CompleteZone and ReleaseZone against a real zone_coordinator process.

The robot is a test node in ``/robot7``; its planner is a ComputePathToPose action server
on the same node (a straight two-pose path), one that finds no path (every bid ``inf``),
or absent (no bid).
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from fleet_mission import read_events, two_zone_coordinator
from py_trees.common import Status
from sar_plugins.sar.leaves.claim_zone import ClaimZone
from sar_plugins.sar.leaves.complete_zone import CompleteZone
from sar_plugins.sar.leaves.release_zone import ReleaseZone
from sar_testing.leaf_harness import spec_zone_manager, tick_until_done, tree_on
from sar_testing.spin import ros_node, spin_until

from sar_framework.testing import declared_leaf

pytestmark = pytest.mark.ros

@pytest.fixture
def coordinator(tmp_path: Path) -> Iterator[Path]:
    events = tmp_path / "events.jsonl"
    with two_zone_coordinator(tmp_path, "-p", f"events_file:={events}",
                              "-p", "bid_window_wall_s:=1.0",
                              "-p", "abandon_after_rounds:=1") as proc:
        proc.wait_for_output("ready", timeout=20.0)
        yield events


@pytest.fixture
def robot() -> Iterator[tuple[Any, Any]]:
    with ros_node("sar_mission_runner", namespace="/robot7") as pair:
        yield pair


def planner(node: Any) -> Any:
    """A ComputePathToPose server: a straight path from (0, 0) to the goal."""
    from geometry_msgs.msg import PoseStamped
    from nav2_msgs.action import ComputePathToPose
    from rclpy.action import ActionServer

    def execute(handle: Any) -> Any:
        result = ComputePathToPose.Result()
        start, end = PoseStamped(), PoseStamped()
        end.pose.position = handle.request.goal.pose.position
        result.path.poses = [start, end]
        handle.succeed()
        return result

    return ActionServer(node, ComputePathToPose, "compute_path_to_pose", execute)


def test_claim_wins_the_nearest_zone_then_complete_reports_it(coordinator: Path,
                                                              robot: tuple) -> None:
    node, executor = robot
    server = planner(node)
    zones = spec_zone_manager([{"id": "zone_a", "x": -3.0, "y": 3.0, "yaw": 0.0},
                               {"id": "zone_b", "x": 3.5, "y": 3.0, "yaw": 1.57}])
    claim = declared_leaf(ClaimZone, "ClaimZone", zone_manager=zones)
    tree = tree_on(node, claim)
    assert tick_until_done(executor, tree, 20.0) == Status.SUCCESS, claim.feedback_message
    # a loaded machine may deliver the first round's bid after its window: the next round
    assert re.fullmatch(r"robot7 won zone_a in auction \d+ \(4\.24 m\)",
                        claim.feedback_message), claim.feedback_message
    assert zones.current_zone()["id"] == "zone_a"
    complete = declared_leaf(CompleteZone, "CompleteZone", zone_manager=zones)
    assert tick_until_done(executor, tree_on(node, complete), 20.0) == Status.SUCCESS
    assert complete.feedback_message == "zone_a searched (coordinator told)"
    zones.advance()
    assert tick_until_done(executor, tree, 20.0) == Status.SUCCESS
    assert zones.current_zone()["id"] == "zone_b"
    release = declared_leaf(ReleaseZone, "ReleaseZone", zone_manager=zones)
    assert tick_until_done(executor, tree_on(node, release), 20.0) == Status.SUCCESS
    # Given back by the only robot: abandoned; no work is left, at once from now on.
    assert tick_until_done(executor, tree, 20.0) == Status.FAILURE
    assert claim.feedback_message == "no work left: every zone is searched or abandoned"
    tree.tick()
    assert claim.status == Status.FAILURE
    kinds = [(e["kind"], e["robot"], e["zone_id"]) for e in read_events(coordinator)]
    assert ("robot_joined", "robot7", "") in kinds
    assert ("searched", "robot7", "zone_a") in kinds
    assert ("given_back", "robot7", "zone_b") in kinds
    assert ("abandoned", "", "zone_b") in kinds
    server.destroy()


def test_without_a_planner_answer_the_robot_does_not_bid_and_the_zones_stay_open(
        coordinator: Path, robot: tuple) -> None:
    # Not knowing (no planner yet, or a busy one) is not "cannot reach": before the fix every
    # bid was inf and an only robot abandoned every zone in its first round.
    node, executor = robot
    claim = declared_leaf(ClaimZone, "ClaimZone", zone_manager=spec_zone_manager(),
                      action_name="no_planner")
    tree = tree_on(node, claim)

    def two_rounds_or_done() -> bool:
        auctions = [e for e in read_events(coordinator) if e["kind"] == "auction"]
        return len(auctions) >= 2 or tree.root.status in (Status.SUCCESS, Status.FAILURE)

    # Rounds of 1 s wall; a loaded machine may need more than two seconds for two of them.
    tree.tick()
    assert spin_until(executor, two_rounds_or_done, 20.0, step=tree.tick)
    assert claim.status == Status.RUNNING, claim.feedback_message
    kinds = [e["kind"] for e in read_events(coordinator)]
    assert kinds.count("auction") >= 2 and "bid" not in kinds and "abandoned" not in kinds


def test_a_planner_that_finds_no_path_bids_inf_and_the_zones_are_abandoned(
        coordinator: Path, robot: tuple) -> None:
    from nav2_msgs.action import ComputePathToPose
    from rclpy.action import ActionServer

    def no_path(handle: Any) -> Any:
        handle.abort()
        return ComputePathToPose.Result(error_code=208)  # NO_VALID_PATH

    node, executor = robot
    server = ActionServer(node, ComputePathToPose, "compute_path_to_pose", no_path)
    claim = declared_leaf(ClaimZone, "ClaimZone", zone_manager=spec_zone_manager())
    assert tick_until_done(executor, tree_on(node, claim), 20.0) == Status.FAILURE
    assert claim.feedback_message == "no work left: every zone is searched or abandoned"
    bid = next(e for e in read_events(coordinator) if e["kind"] == "bid")
    assert bid["robot"] == "robot7" and bid["costs"] == [None] * len(bid["zone_ids"])
    server.destroy()


def test_finishing_a_zone_not_held_is_refused_with_the_reason(coordinator: Path,
                                                             robot: tuple) -> None:
    node, executor = robot
    leaf = declared_leaf(ReleaseZone, "ReleaseZone", zone_manager=spec_zone_manager())
    assert tick_until_done(executor, tree_on(node, leaf), 20.0) == Status.FAILURE
    assert leaf.feedback_message == ("the coordinator refused zone_a given back: robot7 "
                                     "does not hold zone_a (it is open)")


def test_no_current_zone_fails_without_asking(robot: tuple) -> None:
    node, executor = robot
    zones = spec_zone_manager([])
    leaf = declared_leaf(CompleteZone, "CompleteZone", zone_manager=zones, server_timeout_s=0.5)
    assert tick_until_done(executor, tree_on(node, leaf), 5.0) == Status.FAILURE
    assert leaf.feedback_message.startswith("no zone to report: no current zone")


def test_without_a_coordinator_claim_fails_after_its_bound_and_beats_from_setup(
        robot: tuple) -> None:
    from sar_fleet_interfaces.msg import FleetHeartbeat

    from sar_framework.testing.spin import spin_until

    node, executor = robot
    beats: list[str] = []
    node.create_subscription(FleetHeartbeat, "/nowhere/heartbeat",
                             lambda m: beats.append(m.robot), 10)
    leaf = declared_leaf(ClaimZone, "ClaimZone", zone_manager=spec_zone_manager(),
                         server_name="/nowhere",
                         server_timeout_s=1.0, heartbeat_period_wall_s=0.1)
    tree = tree_on(node, leaf)
    assert spin_until(executor, lambda: len(beats) >= 3, 10.0)  # before any tick
    assert set(beats) == {"robot7"}
    assert tick_until_done(executor, tree, 10.0) == Status.FAILURE
    assert leaf.feedback_message == ("cannot ask for work: /nowhere/request_zone service "
                                     "not available after 1.0 s")
    tree.shutdown()
