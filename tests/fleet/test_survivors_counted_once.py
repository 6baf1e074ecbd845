"""Survivors counted once across a fleet, over real DDS.

One rclpy context holds the coordinator's node (root namespace, hosting
SurvivorRegistryService) and two robots' runner nodes (``/robot1``, ``/robot2``, with
nav2_bringup's TF remapping, so each broadcasts on its own ``tf_static``). Each robot ticks
``fixtures/survivor_branch.yaml`` (the survivor branch of a fleet tree), built from YAML with
the real leaves. Child processes: a detect server per robot namespace (robot2 sees the same
survivor 0.5 m away from where robot1 sees it) and the real base, ``report_survivor_server``,
whose report file must hold each survivor exactly once.
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import py_trees
import pytest
from py_trees.common import Status
from sar_plugins.sar.events import SarKind
from sar_plugins.sar.fleet.survivor_registry import Registration
from sar_plugins.sar.fleet.survivor_service import (
    REGISTER_SURVIVOR_SERVICE,
    SurvivorRegistryService,
)
from sar_plugins.sar.leaves.log_survivor_not_registered import LogSurvivorNotRegistered
from sar_plugins.sar.leaves.register_survivor import RegisterSurvivor
from sar_testing.leaf_harness import TfStaticRecorder, spec_zone_manager, tree_on
from sar_testing.processes import NodeProcess
from sar_testing.spin import call_service, spin_until

from sar_framework import load_tree
from sar_framework.events.emitter import EventEmitter
from sar_framework.events.event import EventKind
from sar_framework.ros.tf_topics import TF_REMAP_ARGS
from sar_framework.testing import declared_leaf

pytestmark = pytest.mark.ros
BRANCH = Path(__file__).resolve().parent / "fixtures" / "survivor_branch.yaml"
ROBOT1_SEES = (-2.5, 3.2)  # config/survivors.yaml's zone_a
ROBOT2_SEES = (-2.1, 3.5)  # the same survivor, 0.5 m off
ROBOTS = ("robot1", "robot2")


@pytest.fixture(scope="module")
def detect_servers(tmp_path_factory: pytest.TempPathFactory) -> Iterator[None]:
    """A detect server in each robot's namespace; robot2's sees the survivor elsewhere."""
    folder = tmp_path_factory.mktemp("detect")
    table = folder / "robot2_survivors.yaml"
    table.write_text(f"survivors:\n  zone_a: {{x: {ROBOT2_SEES[0]}, y: {ROBOT2_SEES[1]}}}\n")
    # the server's default name is relative: in /robot1 it serves /robot1/detect_survivor
    module = ["-m", "sar_plugins.sar.servers.detect_survivor_server", "--ros-args"]
    with (NodeProcess([*module, "-r", "__ns:=/robot1"], "detect1", log_dir=folder) as one,
          NodeProcess([*module, "-r", "__ns:=/robot2", "-p", f"survivors_file:={table}"],
                      "detect2", log_dir=folder) as two):
        one.wait_for_output("ready")
        two.wait_for_output("ready")
        yield


@pytest.fixture
def base(tmp_path: Path) -> Iterator[Path]:
    """The real base station; yields its report file."""
    reports = tmp_path / "reports.jsonl"
    with NodeProcess(["-m", "sar_plugins.sar.servers.report_survivor_server", "--ros-args",
                      "-p", f"report_file:={reports}"], "base", log_dir=tmp_path) as process:
        process.wait_for_output("ready")
        yield reports


class Fleet:
    """The coordinator's node with the registry service, and one runner node per robot."""

    def __init__(self, node: Any, executor: Any) -> None:
        from rclpy.node import Node

        self.executor = executor
        self.registered: list[Registration] = []
        self.service = SurvivorRegistryService(node, radius_m=1.0,
                                               on_registered=self.registered.append)
        self.nodes = {robot: Node("sar_runner", namespace=robot, context=node.context,
                                  cli_args=TF_REMAP_ARGS) for robot in ROBOTS}
        for robot_node in self.nodes.values():
            executor.add_node(robot_node)
        self.frames = {robot: TfStaticRecorder(n) for robot, n in self.nodes.items()}
        self.events = {robot: EventEmitter() for robot in ROBOTS}
        self.trees: list[py_trees.trees.BehaviourTree] = []

    def branch(self, robot: str) -> py_trees.trees.BehaviourTree:
        """The survivor branch from YAML, set up on ``robot``'s node, in zone_a."""
        root = load_tree(BRANCH, context={"zone_manager": spec_zone_manager()}).root
        self.trees.append(tree_on(self.nodes[robot], root, self.events[robot]))
        return self.trees[-1]

    def run(self, *trees: py_trees.trees.BehaviourTree, timeout: float = 40.0) -> None:
        """Tick the trees together (one tick each per spin) until every one has finished."""
        def step() -> None:
            for tree in trees:
                if tree.root.status not in (Status.SUCCESS, Status.FAILURE):
                    tree.tick()

        step()
        assert spin_until(self.executor, lambda: all(
            t.root.status in (Status.SUCCESS, Status.FAILURE) for t in trees), timeout,
            step=step), [t.root.tip().feedback_message for t in trees if t.root.tip()]

    def close(self) -> None:
        for tree in self.trees:
            tree.shutdown()
        self.service.destroy()
        for robot_node in self.nodes.values():
            self.executor.remove_node(robot_node)
            robot_node.destroy_node()


@pytest.fixture
def fleet(ros: tuple, detect_servers: None) -> Iterator[Fleet]:
    node, executor = ros
    made = Fleet(node, executor)
    yield made
    made.close()


def leaf(tree: py_trees.trees.BehaviourTree, cls: type) -> Any:
    (found,) = [b for b in tree.root.iterate() if isinstance(b, cls)]
    return found


def report_lines(reports: Path) -> list[dict[str, Any]]:
    return [json.loads(line) for line in reports.read_text().splitlines() if line.strip()]


def notes(fleet: Fleet, robot: str) -> list[str]:
    return [e.message for e in fleet.events[robot].emitted if e.kind == EventKind.NOTE]


def test_the_same_survivor_from_two_robots_gets_one_id_one_frame_one_report(
        fleet: Fleet, base: Path) -> None:
    trees = {robot: fleet.branch(robot) for robot in ROBOTS}
    fleet.run(*trees.values())

    assert all(tree.root.status == Status.SUCCESS for tree in trees.values())
    first, repeat = fleet.registered
    assert (first.survivor_id, first.first, first.report) == ("survivor_1", True, True)
    assert (repeat.survivor_id, repeat.first, repeat.report) == ("survivor_1", False, False)
    reporter, other = first.robot, repeat.robot
    assert {reporter, other} == set(ROBOTS)

    assert {robot: leaf(trees[robot], RegisterSurvivor).robot for robot in ROBOTS} == \
        {"robot1": "robot1", "robot2": "robot2"}, "the robot is the node's namespace"
    assert leaf(trees[reporter], RegisterSurvivor).survivor_id() == "survivor_1"
    register = leaf(trees[other], RegisterSurvivor)
    assert register.status == Status.FAILURE and register.survivor_id() is None
    assert register.feedback_message.startswith("Survivor at ")
    assert ("is survivor_1, found by " + reporter + ": not reported again (survivor_1 was "
            f"registered first by {reporter}, which reports it).") in register.feedback_message
    assert leaf(trees[other], LogSurvivorNotRegistered).status == Status.SUCCESS
    # the duplicate was noted once (by RegisterSurvivor), and never read as "no survivor"
    assert notes(fleet, other) == [register.feedback_message]
    assert not any("No survivor found" in n for robot in ROBOTS for n in notes(fleet, robot))
    broadcasts = {robot: [e.value("survivor_id") for e in fleet.events[robot].emitted
                          if e.kind == SarKind.SURVIVOR_BROADCAST] for robot in ROBOTS}
    reported = {robot: [e.value("survivor_id") for e in fleet.events[robot].emitted
                        if e.kind == SarKind.SURVIVOR_REPORTED] for robot in ROBOTS}
    assert broadcasts == {reporter: ["survivor_1"], other: []}
    assert reported == {reporter: ["survivor_1"], other: []}

    assert spin_until(fleet.executor,
                      lambda: fleet.frames[reporter].child_frames() == {"survivor_1"}, 5.0)
    assert fleet.frames[other].child_frames() == set()
    assert [line["survivor_id"] for line in report_lines(base)] == ["survivor_1"]


def test_a_survivor_whose_reporter_is_lost_is_reported_by_the_next_finder(
        fleet: Fleet, base: Path) -> None:
    from sar_plugins.sar.leaves.detect_survivor import DetectSurvivor

    # robot1 detects and registers, then "dies" before it broadcasts or reports
    zones = spec_zone_manager()
    detect = declared_leaf(DetectSurvivor, "detect", zone_manager=zones)
    register = declared_leaf(RegisterSurvivor, "register", detector=detect)
    dying = tree_on(fleet.nodes["robot1"], py_trees.composites.Sequence(
        "DetectAndRegister", memory=True, children=[detect, register]))
    fleet.trees.append(dying)
    fleet.run(dying)
    assert register.status == Status.SUCCESS and register.survivor_id() == "survivor_1"

    # while robot1 counts as alive, robot2 only notes the duplicate
    early = fleet.branch("robot2")
    fleet.run(early)
    assert leaf(early, RegisterSurvivor).duplicate() is not None
    assert report_lines(base) == []

    assert fleet.service.robot_lost("robot1") == ("survivor_1",)
    later = fleet.branch("robot2")
    fleet.run(later)
    assert later.root.status == Status.SUCCESS
    assert leaf(later, RegisterSurvivor).survivor_id() == "survivor_1"
    assert fleet.registered[-1].takeover and fleet.registered[-1].robot == "robot2"
    assert spin_until(fleet.executor,
                      lambda: fleet.frames["robot2"].child_frames() == {"survivor_1"}, 5.0)
    assert fleet.frames["robot1"].child_frames() == set()
    (line,) = report_lines(base)
    assert line["survivor_id"] == "survivor_1"
    assert (line["x"], line["y"]) == ROBOT2_SEES


def test_a_refused_registration_is_logged_and_not_broadcast(fleet: Fleet) -> None:
    from sar_fleet_interfaces.srv import RegisterSurvivor as RegisterSurvivorSrv

    class NotFinite:
        def was_found(self) -> bool:
            return True

        def survivor_pose(self) -> tuple[float, float]:
            return (math.nan, 1.0)

        def zone_id(self) -> str:
            return "zone_a"

    register = declared_leaf(RegisterSurvivor, "register", detector=NotFinite())  # type: ignore[arg-type]
    log = LogSurvivorNotRegistered("NotOursToReport?", registrar=register)
    tree = tree_on(fleet.nodes["robot1"], py_trees.composites.Selector(
        "Handle", memory=False, children=[register, log]), fleet.events["robot1"])
    fleet.trees.append(tree)
    fleet.run(tree)
    assert register.status == Status.FAILURE and register.duplicate() is None
    expected = ("Survivor at (nan, 1.00) not registered: registration refused: x: must be a "
                "finite number of metres, got nan")
    assert register.failed_registration() == expected
    assert tree.root.status == Status.SUCCESS and log.feedback_message == expected
    assert notes(fleet, "robot1") == [expected]
    assert fleet.registered == []

    nameless = call_service(fleet.nodes["robot1"], fleet.executor, RegisterSurvivorSrv,
                            REGISTER_SURVIVOR_SERVICE,
                            RegisterSurvivorSrv.Request(robot="", x=1.0, y=2.0))
    assert (nameless.survivor_id, nameless.report) == ("", False)
    assert nameless.reason == "registration refused: robot: must be a non-empty name, got ''"
    assert fleet.service.survivor_ids() == ()


def test_a_broadcaster_whose_registrar_gave_no_id_broadcasts_nothing(fleet: Fleet) -> None:
    from sar_plugins.sar.leaves.broadcast_survivor_tf import BroadcastSurvivorTF

    class Found:
        def was_found(self) -> bool:
            return True

        def survivor_pose(self) -> tuple[float, float]:
            return ROBOT1_SEES

    class NoId:
        name = "register"

        def survivor_id(self) -> None:
            return None

    zones = spec_zone_manager()
    broadcast = declared_leaf(
        BroadcastSurvivorTF, "broadcast", zone_manager=zones,
        detector=Found(),  # type: ignore[arg-type]
        registrar=NoId())  # type: ignore[arg-type]
    tree = tree_on(fleet.nodes["robot1"], broadcast)
    fleet.trees.append(tree)
    tree.tick()
    assert broadcast.status == Status.FAILURE
    assert broadcast.feedback_message == "no fleet survivor id from register to broadcast"
    assert zones.next_survivor_id() == "survivor_1", "no local id was allocated"
    spin_until(fleet.executor, lambda: False, 0.5)
    assert fleet.frames["robot1"].child_frames() == set()
