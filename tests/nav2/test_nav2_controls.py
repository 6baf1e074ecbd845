"""Nav2's ROS-free controls and decorators, ticked in py_trees with scripted leaves.

Nav2's nodes are not part of BehaviorTree.CPP, so these tests check the behaviour read
from ``nav2_behavior_tree`` (Jazzy): ``recovery_node.cpp``, ``pipeline_sequence.cpp``,
``round_robin_node.cpp``, ``rate_controller.cpp`` and ``single_trigger_node.cpp``.
"""

from __future__ import annotations

from pathlib import Path

import py_trees
import pytest
from engine.scripted_leaves import Clock, Log, Scripted, tick
from py_trees.common import Status
from sar_plugins.nav2.controls import (
    PipelineSequence,
    RecoveryNode,
    RoundRobin,
)
from sar_plugins.nav2.decorators import RateController, SingleTrigger

from sar_framework.engine.api import load_tree
from sar_framework.engine.building.control_build import CLOCK_KEY
from sar_framework.engine.diagnostics import TreeLoadError
from sar_framework.engine.nodes.controls.conditionals import WhileDoElse
from sar_framework.engine.nodes.controls.sequences import Sequence
from sar_framework.engine.registry import Registry


def test_recovery_node_recovers_up_to_number_of_retries() -> None:
    log = Log()
    action = Scripted("Action", ["FAILURE", "FAILURE", "FAILURE", "SUCCESS"], log)
    recovery = Scripted("Recover", ["RUNNING", "SUCCESS"], log)
    node = RecoveryNode("R", [action, recovery], number_of_retries=2)
    assert tick(node) == Status.RUNNING  # Action fails, Recover runs
    assert tick(node) == Status.FAILURE  # Recover ok, Action fails, Recover ok, Action fails
    assert log.visits == ["Action FAILURE", "Recover RUNNING", "Recover SUCCESS",
                          "Action FAILURE", "Recover SUCCESS", "Action FAILURE"]
    log.visits.clear()
    assert tick(node) == Status.SUCCESS  # retries were reset: Action succeeds at once
    assert log.visits == ["Action SUCCESS"]


def test_recovery_node_fails_when_the_recovery_fails_and_skips_with_its_action() -> None:
    log = Log()
    node = RecoveryNode("R", [Scripted("A", ["FAILURE"], log),
                              Scripted("B", ["FAILURE"], log)])
    assert tick(node) == Status.FAILURE
    assert log.visits == ["A FAILURE", "B FAILURE"]
    skipped = RecoveryNode("S", [Scripted("A", ["SKIPPED"], log), Scripted("B", [], log)])
    tick(skipped)
    assert skipped.status == Status.SUCCESS and getattr(skipped, "sar_skipped", False)
    recovery_skipped = RecoveryNode("T", [Scripted("A", ["FAILURE"], log),
                                          Scripted("B", ["SKIPPED"], log)], 3)
    assert tick(recovery_skipped) == Status.FAILURE


def test_recovery_node_needs_two_children() -> None:
    with pytest.raises(ValueError, match="exactly 2 children"):
        RecoveryNode("R", [py_trees.behaviours.Success("A")])


def test_pipeline_sequence_re_ticks_earlier_children() -> None:
    log = Log()
    first = Scripted("Plan", ["SUCCESS", "RUNNING", "SUCCESS"], log)
    second = Scripted("Follow", ["RUNNING", "RUNNING", "SUCCESS"], log)
    node = PipelineSequence("P", [first, second])
    assert [tick(node) for _ in range(3)] == [Status.RUNNING] * 2 + [Status.SUCCESS]
    # Plan runs again on the 2nd tick, yet Follow (further on) is still ticked.
    assert log.visits == ["Plan SUCCESS", "Follow RUNNING", "Plan RUNNING", "Follow RUNNING",
                          "Plan SUCCESS", "Follow SUCCESS"]


def test_pipeline_sequence_fails_and_halts_on_a_failure() -> None:
    log = Log()
    follow = Scripted("Follow", ["RUNNING"], log)
    node = PipelineSequence("P", [Scripted("Plan", ["SUCCESS", "FAILURE"], log), follow])
    assert tick(node) == Status.RUNNING
    assert tick(node) == Status.FAILURE
    assert follow.halted == 1 and follow.status == Status.INVALID


def test_round_robin_order_across_ticks() -> None:
    log = Log()
    a = Scripted("A", ["SUCCESS"], log)
    b = Scripted("B", ["RUNNING", "SUCCESS"], log)
    c = Scripted("C", ["FAILURE", "SUCCESS"], log)
    node = RoundRobin("RR", [a, b, c])
    results = [tick(node) for _ in range(5)]
    assert results == [Status.SUCCESS, Status.RUNNING, Status.SUCCESS, Status.SUCCESS,
                       Status.SUCCESS]
    assert log.visits == ["A SUCCESS", "B RUNNING", "B SUCCESS", "C FAILURE", "A SUCCESS",
                          "B SUCCESS"]


def test_round_robin_fails_after_every_child_failed_in_a_row() -> None:
    log = Log()
    node = RoundRobin("RR", [Scripted(n, ["FAILURE"], log) for n in "ABC"])
    assert tick(node) == Status.FAILURE
    assert log.visits == ["A FAILURE", "B FAILURE", "C FAILURE"]


def test_rate_controller_ticks_the_child_at_most_hz_times_a_second() -> None:
    log, clock = Log(), Clock()
    rate = RateController("Rate", Scripted("Plan", ["SUCCESS"], log), hz=2.0, clock=clock)
    pipeline = PipelineSequence("P", [rate, Scripted("Follow", ["RUNNING"], log)])
    for now in (0.0, 0.2, 0.4, 0.5, 0.7, 1.0):
        clock.now = now
        assert tick(pipeline) == Status.RUNNING
    # The first tick at once; then once 0.5 s passed since the last success.
    assert [v for v in log.visits if v.startswith("Plan")] == ["Plan SUCCESS"] * 3
    assert log.visits[:4] == ["Plan SUCCESS", "Follow RUNNING", "Follow RUNNING",
                              "Follow RUNNING"]
    assert log.visits[4:6] == ["Plan SUCCESS", "Follow RUNNING"]


def test_rate_controller_ticks_a_running_child_every_time_and_rearms_when_reset() -> None:
    log, clock = Log(), Clock()
    child = Scripted("Plan", ["RUNNING", "RUNNING", "SUCCESS", "SUCCESS"], log)
    node = RateController("Rate", child, hz=1.0, clock=clock)
    parent = Sequence("S", [node])  # a Sequence resets its finished children
    for now in (0.0, 0.1, 0.2, 0.3):
        clock.now = now
        tick(parent)
    assert log.visits == ["Plan RUNNING", "Plan RUNNING", "Plan SUCCESS", "Plan SUCCESS"]


def test_single_trigger_fires_once_until_reset() -> None:
    log = Log()
    trigger = SingleTrigger("Once", Scripted("Fire", ["RUNNING", "SUCCESS"], log))
    node = WhileDoElse("W", [trigger, Scripted("Do", ["RUNNING"], log),
                             Scripted("Else", ["RUNNING"], log)])
    assert [tick(node) for _ in range(4)] == [Status.RUNNING] * 4
    assert log.visits == ["Fire RUNNING", "Fire SUCCESS", "Do RUNNING", "Else RUNNING",
                          "Else RUNNING"]
    node.stop(Status.INVALID)  # halting the parent resets the trigger: it fires again
    log.visits.clear()
    tick(node)
    assert log.visits == ["Fire SUCCESS", "Do RUNNING"]


def test_nav2_kinds_load_from_a_tree_file(tmp_path: Path, registry: Registry) -> None:
    path = tmp_path / "nav2.yaml"
    path.write_text("format: 1\nroot:\n  RecoveryNode:\n    number_of_retries: 3\n"
                    "    children:\n      - PipelineSequence:\n          children:\n"
                    "            - RateController: {hz: 2, child: {Fixed: {status: success}}}\n"
                    "            - SingleTrigger: {child: {Fixed: {status: running}}}\n"
                    "      - RoundRobin: {children: [Fixed: {status: failure}]}\n")
    clock = Clock()
    root = load_tree(path, {CLOCK_KEY: clock}, registry=registry).root
    assert isinstance(root, RecoveryNode) and root.number_of_retries == 3
    rate = root.children[0].children[0]
    assert isinstance(rate, RateController) and rate.clock is clock and rate.hz == 2.0
    root.tick_once()
    assert root.status == Status.RUNNING


def test_a_recovery_node_with_three_children_is_a_located_error(tmp_path: Path,
                                                                registry: Registry) -> None:
    path = tmp_path / "bad.yaml"
    path.write_text("format: 1\nroot:\n  RecoveryNode:\n    children:\n"
                    "      - Fixed: {status: success}\n      - Fixed: {status: success}\n"
                    "      - Fixed: {status: success}\n")
    with pytest.raises(TreeLoadError, match=r"bad.yaml:5:7: error: RecoveryNode takes at "
                       r"most 2 children, got 3"):
        load_tree(path, {}, registry=registry)
