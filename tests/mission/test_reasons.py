"""Reason records: one per failure, timeout, cancel, retry and skip, with node and why (no ROS)."""

from __future__ import annotations

import time
from pathlib import Path

import py_trees
from py_trees.common import Status
from sar_plugins.sar.zone_manager import ZoneManager

from sar_framework import load_tree
from sar_framework.runner.reasons import reason_line
from sar_framework.runner.status_file import StatusFileWriter

PLUGINS = Path(__file__).resolve().parent / "runner_plugins"

TREE = """\
format: 1
name: reasons
root:
  sequence:
    memory: true
    name: Steps
    children:
      - failure_is_success:
          name: SkipA
          child:
            retry:
              name: RetryA
              num_failures: 2
              child:
                Countdown: {name: NavA, ticks: 1, succeed: false, message: "goal to zone_a aborted"}
      - failure_is_success:
          name: SkipB
          child:
            timeout:
              name: WithinB
              duration: 0.2
              child:
                Countdown: {name: NavB, ticks: 100000}
      - selector:
          name: Reactive
          memory: false
          children:
            - Countdown: {name: Later, ticks: 1, succeed: false, message: "not yet"}
            - Countdown: {name: Long, ticks: 100000}
"""


def _run(tmp_path: Path, ticks: int) -> StatusFileWriter:
    path = tmp_path / "t.yaml"
    path.write_text(TREE)
    zones = ZoneManager([{"id": "zone_a", "x": 0.0, "y": 0.0, "yaw": 0.0}],
                        {"x": 0.0, "y": 0.0, "yaw": 0.0})
    loaded = load_tree(path, context={"zone_manager": zones}, plugin_paths=[PLUGINS])
    writer = StatusFileWriter(str(path), loaded.spec, loaded.behaviours, lambda: 0.0)
    tree = py_trees.trees.BehaviourTree(loaded.root)
    tree.visitors.append(writer)
    tree.add_post_tick_handler(writer.after_tick)
    for _ in range(ticks):
        tree.tick()
        time.sleep(0.01)
        if writer.status != Status.RUNNING:
            break
    return writer


def test_every_failure_retry_skip_timeout_and_cancel_has_a_line(tmp_path: Path) -> None:
    """Regression: a timeout, retry or skip printed nothing; mission.json had no failures."""
    writer = _run(tmp_path, 60)
    lines = [reason_line(r) for r in writer.new_reasons]
    assert lines[:5] == [
        "NavA [0.0.0.0]: goal to zone_a aborted",
        "RetryA [0.0.0] retry: attempt 1/2 failed (goal to zone_a aborted); trying again",
        "NavA [0.0.0.0]: goal to zone_a aborted",
        "RetryA [0.0.0] retry: giving up after 2 failed attempts (goal to zone_a aborted)",
        "SkipA [0.0] skip: RetryA failed (goal to zone_a aborted); skipped",
    ]
    assert lines[5].startswith("WithinB [0.1.0] timeout: timed out after 0.2 s; NavB: ")
    assert lines[6].startswith("SkipB [0.1] skip: WithinB failed (timed out after 0.2 s; NavB")
    # the reactive selector: Later fails after running, Long runs, Later runs again and
    # halts Long (a cancel)
    assert "Later [0.2.0]: not yet" in lines
    assert any(line.startswith("Long [0.2.1] cancel: halted (") for line in lines)
    assert writer.failures == writer.new_reasons
    assert {r["what"] for r in writer.failures} == {"failure", "retry", "skip", "timeout",
                                                      "cancel"}


CONDITION = """\
format: 1
name: condition
root:
  sequence:
    memory: true
    name: Steps
    children:
      - failure_is_success:
          name: BudgetOver
          child:
            sequence:
              name: Budget200s
              memory: true
              children:
                - Countdown: {name: CheckBattery, ticks: 0, succeed: false,
                              message: "battery at 12 %, below 20 %"}
                - Countdown: {name: Patrol, ticks: 1}
      - Countdown: {name: CheckAgain, ticks: 1, succeed: false, message: "still at 12 %"}
"""


def test_a_condition_s_reason_reaches_what_fails_because_of_it(tmp_path: Path) -> None:
    """Regression: 'BudgetOver skip: Budget200s failed (no reason given)'; the reason of a
    leaf that failed without RUNNING first (a user's condition) was only in runner.log."""
    path = tmp_path / "t.yaml"
    path.write_text(CONDITION)
    zones = ZoneManager([{"id": "zone_a", "x": 0.0, "y": 0.0, "yaw": 0.0}],
                        {"x": 0.0, "y": 0.0, "yaw": 0.0})
    loaded = load_tree(path, context={"zone_manager": zones}, plugin_paths=[PLUGINS])
    recorder = StatusFileWriter(str(path), loaded.spec, loaded.behaviours, lambda: 0.0,
                              completion="once")
    tree = py_trees.trees.BehaviourTree(loaded.root)
    tree.visitors.append(recorder)
    tree.add_post_tick_handler(recorder.after_tick)
    tree.tick()
    tree.tick()
    lines = [reason_line(r) for r in recorder.failures]
    assert lines == [
        "BudgetOver [0.0] skip: Budget200s failed (CheckBattery: battery at 12 %, below 20 %); "
        "skipped",
        "CheckAgain [0.1]: still at 12 %",  # the root failed because of it
    ]


RECOVERY = """\
format: 1
name: recovery
root:
  RecoveryNode:
    name: Recover
    number_of_retries: 2
    children:
      - Countdown: {name: Act, ticks: 1, succeed: false, message: "goal occupied"}
      - Sequence:
          children:
            - Countdown: {name: Ready, ticks: 0, succeed: true, message: ""}
            - Countdown: {name: Clear, ticks: 1, succeed: true, message: "cleared"}
"""


_RECOVERED = "after Act: goal occupied; trying Act again"
#: The reason lines of RECOVERY: two recoveries, then giving up.
TWO_RECOVERIES = [
    "Act [0.0]: goal occupied",
    f"Recover [0] retry: recovery 1/2 done (Countdown Clear) {_RECOVERED}",
    "Act [0.0]: goal occupied",
    f"Recover [0] retry: recovery 2/2 done (Countdown Clear) {_RECOVERED}",
    "Act [0.0]: goal occupied",
    "Recover [0] retry: giving up after 2/2 recoveries (Act: goal occupied)",
]


def recovery_reasons(tmp_path: Path, text: str, ticks: int) -> list[str]:
    """The reason lines of a RecoveryNode tree ticked ``ticks`` times (or until it fails)."""
    path = tmp_path / "t.yaml"
    path.write_text(text)
    zones = ZoneManager([], {"x": 0.0, "y": 0.0, "yaw": 0.0})
    loaded = load_tree(path, context={"zone_manager": zones}, plugin_paths=[PLUGINS])
    writer = StatusFileWriter(str(path), loaded.spec, loaded.behaviours, lambda: 0.0,
                              completion="once")
    tree = py_trees.trees.BehaviourTree(loaded.root)
    tree.visitors.append(writer)
    tree.add_post_tick_handler(writer.after_tick)
    for _ in range(ticks):
        tree.tick()
        if loaded.root.status == Status.FAILURE:
            break
    assert loaded.root.status == Status.FAILURE
    return [reason_line(r) for r in writer.failures]


def test_a_recovery_node_says_each_recovery_and_when_it_gives_up(tmp_path: Path) -> None:
    """Nav2's RecoveryNode: the action's failure, each recovery that let it try again (the
    recovery's actions named, not its conditions), then giving up."""
    assert recovery_reasons(tmp_path, RECOVERY, 20) == TWO_RECOVERIES


def test_a_recovery_that_fails_fails_the_recovery_node_saying_both_reasons(
        tmp_path: Path) -> None:
    text = RECOVERY.replace('succeed: true, message: "cleared"',
                            'succeed: false, message: "service gone"')
    assert recovery_reasons(tmp_path, text, 5) == [
        "Act [0.0]: goal occupied",
        "Clear [0.1.1]: service gone",
        "Recover [0] retry: giving up: the recovery of Act failed (Clear: service gone) "
        "after Act: goal occupied",
    ]


def test_a_recovery_node_with_a_post_condition_still_says_its_recoveries(
        tmp_path: Path) -> None:
    """Its behaviour is then the pre/post-condition wrapper; the reasons read the node inside."""
    text = RECOVERY.replace("    number_of_retries: 2\n",
                            '    number_of_retries: 2\n    _post: "done := true"\n')
    text = text.replace("name: recovery\n",
                        "name: recovery\nblackboard:\n  done: {type: bool, initial: false}\n")
    assert recovery_reasons(tmp_path, text, 20) == TWO_RECOVERIES
