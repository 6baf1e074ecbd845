"""sar_framework.testing in this project's own run: fixtures, assertions, the ROS stack."""

from __future__ import annotations

from pathlib import Path

import py_trees
import pytest
from sar_testing.leaf_harness import spec_zone_manager

from sar_framework.engine.api import TreeLoadError
from sar_framework.testing import (
    assert_feedback,
    assert_feedback_text,
    assert_status,
    assert_statuses,
)
from sar_framework.testing.ros_harness import tick_until_done, tree_on

HERE = Path(__file__).parent
KIT_LEAVES = HERE / "kit_leaves.py"
TUTORIAL_LEAVES = HERE.parents[1] / "trees" / "tutorials" / "plugins" / "tutorial_leaves.py"


def test_a_scripted_blackboard_is_set_before_each_tick(sar_leaf) -> None:
    run = sar_leaf("LevelAboveZero", plugin_paths=[KIT_LEAVES],
                   blackboard=[{"/level": 3}, {"/level": 0}, {"/level": 7}])
    run.tick(3)
    assert_statuses(run, ["SUCCESS", "FAILURE", "SUCCESS"])
    assert_feedback(run, r"^level 0$", tick=2)
    assert run.feedback() == ["level 3", "level 0", "level 7"]


def test_the_blackboard_is_cleared_after_a_test() -> None:
    assert py_trees.blackboard.Blackboard.storage == {}


def test_a_whole_tree_document_with_its_own_plugins(sar_tree, tmp_path) -> None:
    run = sar_tree(f"""
        format: 1
        name: waits
        plugins: [{TUTORIAL_LEAVES}]
        root:
          sequence:
            name: WaitThenFail
            memory: true
            children:
              - Countdown: {{name: Wait, ticks: 2}}
              - Countdown: {{name: Fail, ticks: 0, result: failure}}
    """)
    assert run.tick_until_done() == py_trees.common.Status.FAILURE
    assert_statuses(run, ["RUNNING", "RUNNING", "SUCCESS"], name="Wait")
    assert_feedback(run, "done", name="Fail")


def test_failed_assertions_show_the_history(sar_leaf) -> None:
    run = sar_leaf("Countdown", {"ticks": 1}, plugin_paths=[TUTORIAL_LEAVES])
    run.tick(2)
    with pytest.raises(AssertionError, match=r"(?s)expected \['RUNNING', 'FAILURE'\].*"
                                             r"tick 2: Countdown=SUCCESS"):
        assert_statuses(run, ["RUNNING", "FAILURE"])
    with pytest.raises(AssertionError, match="Countdown is SUCCESS, expected RUNNING"):
        assert_status(run, "RUNNING")
    with pytest.raises(AssertionError, match="does not match 'to go'"):
        assert_feedback(run, "to go")
    with pytest.raises(KeyError, match="0 behaviours are called 'Nope'"):
        run.statuses("Nope")


def test_an_invalid_tree_raises_with_every_problem(sar_tree) -> None:
    with pytest.raises(TreeLoadError, match=r"(?s)'memory: true'.*unknown plugin 'Contdown'"):
        sar_tree("""
            sequence:
              children:
                - Contdown: {}
        """, plugin_paths=[TUTORIAL_LEAVES])


@pytest.mark.ros
def test_the_mission_stack_serves_a_real_detect_leaf(sar_mission_stack, sar_ros_node,
                                                      sar_tree) -> None:
    node, executor = sar_ros_node
    run = sar_tree("DetectSurvivor: {id: detect}", context={"zone_manager": spec_zone_manager()})
    tree = tree_on(node, run.root)
    try:
        assert tick_until_done(executor, tree, timeout=30.0) == py_trees.common.Status.SUCCESS
    finally:
        tree.shutdown()
    assert "Detection request for zone_a" in sar_mission_stack.output("detect")
    assert "ready" in sar_mission_stack.output("sim")


def test_a_run_shows_the_trees_blackboard_entries(sar_tree) -> None:
    run = sar_tree("""
        format: 1
        name: counts
        blackboard:
          count: {type: int, initial: 0}
          label: {type: str}
        root:
          sequence:
            memory: true
            children:
              - Script: {code: "count := count + 1"}
              - SetBlackboard: {value: "seen", output_key: label}
    """)
    assert run.entries() == {"count": 0}  # written before the first tick; label not yet
    run.tick()
    assert run.entries() == {"count": 1, "label": "seen"}
    run.tick()
    assert run.entry("count") == 2
    assert [record.entries["count"] for record in run.history] == [1, 2]
    with pytest.raises(KeyError, match="no entry 'cuont' \\(did you mean 'count'\\?\\)"):
        run.entry("cuont")


def test_an_entry_not_set_yet_is_a_key_error(sar_tree) -> None:
    run = sar_tree("""
        format: 1
        name: later
        blackboard:
          label: {type: str}
        root:
          SetBlackboard: {value: "x", output_key: label}
    """)
    with pytest.raises(KeyError, match="'label' is not set yet"):
        run.entry("label")


def test_feedback_as_plain_text_beside_the_regular_expression(sar_leaf) -> None:
    run = sar_leaf("Countdown", {"ticks": 0}, plugin_paths=[TUTORIAL_LEAVES])
    run.tick()
    assert run.feedback() == ["done (SUCCESS)"]
    assert_feedback_text(run, "done (SUCCESS)")
    assert_feedback_text(run, "done (SUCCESS)", exact=True)
    assert_feedback(run, r"done \(SUCCESS\)")  # today's calls: a regular expression
    with pytest.raises(AssertionError, match=r"feedback 'done \(SUCCESS\)' is not 'done'"):
        assert_feedback_text(run, "done", exact=True)
    with pytest.raises(AssertionError, match="does not hold 'to go'"):
        assert_feedback_text(run, "to go")


def test_a_regular_expression_that_fails_says_it_is_one(sar_leaf) -> None:
    run = sar_leaf("Countdown", {"ticks": 0}, plugin_paths=[TUTORIAL_LEAVES])
    run.tick()
    with pytest.raises(AssertionError) as failed:
        assert_feedback(run, "done (SUCCESS)")
    assert ("note: 'done (SUCCESS)' is read as a regular expression and holds "
            "regular-expression characters (as plain text it is in the message); "
            "assert_feedback_text compares plain text") in str(failed.value)
    with pytest.raises(AssertionError) as failed:
        assert_feedback(run, "to go")  # nothing special in it: no note
    assert "note:" not in str(failed.value)
    with pytest.raises(AssertionError) as failed:
        assert_feedback(run, "done [(")
    assert "'done [(' is not a regular expression" in str(failed.value)
