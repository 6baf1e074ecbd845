"""py_trees' ``retry`` and ``repeat`` as BT.CPP's ``RetryUntilSuccessful`` and ``Repeat``.

Checked with BehaviorTree.CPP 4.7.3.

What ``retry``'s declaration says (its ``differences``), each point ticked by both sides:
``num_failures`` is written as ``num_attempts`` and both count attempts, the first
included; both count afresh after a halt; a child that fails on its first tick is tried
again on the next tick by both (tick for tick alike); a child that was RUNNING before it
failed is tried again within the same tick by BT.CPP, on the next tick here (the same
visits and result, one tick more per such retry). ``repeat`` likewise, with successes.
"""

from __future__ import annotations

import textwrap
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from interop.scripted import Script, compare, run_checker, run_py_trees, scripted_registry
from sar_framework.engine.api import load_spec
from sar_framework.engine.nodes.node_kinds import KINDS
from sar_framework.engine.registry import Registry, discover
from sar_framework.interop.btcpp_export import export_btcpp

# The first test that needs the checker builds BehaviorTree.CPP (2-3 min on 2 busy cores).
pytestmark = pytest.mark.timeout(1200)
GENERIC = Path(__file__).resolve().parents[2] / "tests" / "engine" / "plugins_for_tests" / "generic"


def _registry() -> Registry:
    return discover([GENERIC], builtins=False, entry_points=False)


def _tree(tmp_path: Path, root: str) -> Path:
    path = tmp_path / "tree.yaml"
    path.write_text("format: 1\nname: t\nroot:\n" + textwrap.indent(textwrap.dedent(root), "  "))
    return path


RETRY = """
    retry:
      num_failures: 3
      child: {Tick: {name: Try}}
    """


def test_num_failures_is_written_as_num_attempts(tmp_path: Path) -> None:
    registry = _registry()
    root = ET.fromstring(export_btcpp(load_spec(_tree(tmp_path, RETRY), registry=registry),
                                      registry))
    (node,) = root.iter("RetryUntilSuccessful")
    assert node.get("num_attempts") == "3"
    assert "RetryUntilSuccessful" in KINDS["retry"].differences


def test_both_make_num_failures_attempts_in_all(btcpp_checker: Path, tmp_path: Path) -> None:
    ours = compare(_tree(tmp_path, RETRY), _registry(), btcpp_checker, {"Try": ["FAILURE"]})
    assert [line for line in ours if line.startswith("visit ")] == ["visit Try FAILURE"] * 3
    assert ours[-1] == "tick 3 FAILURE"


def test_a_child_failing_at_once_is_retried_on_the_next_tick_by_both(
        btcpp_checker: Path, tmp_path: Path) -> None:
    ours = compare(_tree(tmp_path, RETRY), _registry(), btcpp_checker,
                   {"Try": ["FAILURE", "FAILURE", "SUCCESS"]})
    assert ours[-1] == "tick 3 SUCCESS"


def test_both_count_afresh_after_a_halt(btcpp_checker: Path, tmp_path: Path) -> None:
    tree = _tree(tmp_path, """
        sequence:
          memory: false
          children:
            - Tick: {name: Guard}
            - retry:
                num_failures: 2
                child: {Tick: {name: Try}}
        """)
    # Tick 2's failing guard halts the retry after one failure; from tick 3 it has two again.
    script: Script = {"Guard": ["SUCCESS", "FAILURE", "SUCCESS"], "Try": ["FAILURE"]}
    ours = compare(tree, _registry(), btcpp_checker, script, max_ticks=4, all_ticks=True)
    assert [line for line in ours if line.startswith("tick ")] == [
        "tick 1 RUNNING", "tick 2 FAILURE", "tick 3 RUNNING", "tick 4 FAILURE"]


def test_a_child_that_ran_is_retried_within_the_tick_by_btcpp_only(
        btcpp_checker: Path, tmp_path: Path) -> None:
    tree = _tree(tmp_path, RETRY.replace("3", "2"))
    script: Script = {"Try": ["RUNNING", "FAILURE", "RUNNING", "SUCCESS"]}
    ours = compare(tree, _registry(), btcpp_checker, script, exact_ticks=False)
    xml = tree.with_suffix(".xml")
    theirs = run_checker(btcpp_checker, xml, script, 40)
    assert ours == run_py_trees(tree, scripted_registry(_registry()), script, 40)
    assert ours[-1] == "tick 4 SUCCESS"  # RUNNING, FAILURE (RUNNING here), RUNNING, SUCCESS
    assert theirs[-1] == "tick 3 SUCCESS"  # tick 2: FAILURE, then RUNNING in the same tick


def test_repeat_repeats_a_child_that_ran_within_the_tick_in_btcpp_only(
        btcpp_checker: Path, tmp_path: Path) -> None:
    tree = _tree(tmp_path, """
        repeat:
          num_success: 2
          child: {Tick: {name: Again}}
        """)
    script: Script = {"Again": ["RUNNING", "SUCCESS", "RUNNING", "SUCCESS"]}
    ours = compare(tree, _registry(), btcpp_checker, script, exact_ticks=False)
    theirs = run_checker(btcpp_checker, tree.with_suffix(".xml"), script, 40)
    assert (ours[-1], theirs[-1]) == ("tick 4 SUCCESS", "tick 3 SUCCESS")
    assert "Repeat num_cycles=num_success" in KINDS["repeat"].differences
