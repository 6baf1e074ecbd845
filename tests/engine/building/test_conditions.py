"""Pre/post-conditions on a subtree insertion (BT.CPP's ``<SubTree ID="X" _skipIf=...>``).

They wrap the inserted subtree's top node, and their scripts resolve in the *parent's*
scope, as BT.CPP evaluates a SubTree node's own attributes in the parent's blackboard.
"""

from __future__ import annotations

from pathlib import Path

import py_trees
import pytest
from py_trees.common import Status

from sar_framework.engine.api import load_tree
from sar_framework.engine.diagnostics import TreeLoadError
from sar_framework.engine.nodes.skipping import was_skipped
from sar_framework.engine.registry import Registry

from ..conftest import write
from ..port_setup import clean_blackboard  # noqa: F401 (pytest fixture)

Blackboard = py_trees.blackboard.Blackboard

TREE = """format: 1
blackboard:
  busy: {type: bool, initial: true}
  done: {type: bool, initial: false}
subtrees:
  Work:
    ports:
      busy: {direction: input, type: bool, default: false}
    root:
      Fixed: {status: failure}
root:
  Sequence:
    children:
      - subtree: {tree: Work, ports: {busy: false}, _skipIf: busy, _post: "done := true"}
"""


def _load(tmp_path: Path, registry: Registry, text: str) -> py_trees.behaviour.Behaviour:
    return load_tree(write(tmp_path, "tree.yaml", text), {}, registry=registry).root


def test_the_conditions_read_the_parents_entries(tmp_path: Path, registry: Registry) -> None:
    root = _load(tmp_path, registry, TREE)
    root.tick_once()  # the parent's busy is true (the subtree's own is false): skipped
    assert root.status == Status.SUCCESS and was_skipped(root.children[0])
    Blackboard.set("/busy", False)
    root.tick_once()
    assert root.status == Status.FAILURE and Blackboard.get("/done") is True


def test_a_condition_naming_an_entry_the_parent_lacks_is_a_located_error(
        tmp_path: Path, registry: Registry) -> None:
    text = TREE.replace("_skipIf: busy", "_skipIf: bsy")
    with pytest.raises(TreeLoadError, match=r"tree.yaml:14:\d+: error: .*bsy"):
        _load(tmp_path, registry, text)


def test_a_subtree_whose_root_is_an_insertion_keeps_both_conditions(
        tmp_path: Path, registry: Registry) -> None:
    root = _load(tmp_path, registry, """format: 1
blackboard:
  stop: {type: bool, initial: false}
subtrees:
  Inner:
    root:
      Fixed: {status: success}
  Outer:
    blackboard:
      quiet: {type: bool, initial: true}
    root:
      subtree: {tree: Inner, _skipIf: quiet}
root:
  subtree: {tree: Outer, _failureIf: stop}
""")
    root.tick_once()  # Outer's quiet (its own scope) skips Inner
    assert root.status == Status.SUCCESS and was_skipped(root)
    Blackboard.set("/stop", True)  # the main tree's stop fails it before anything runs
    root.tick_once()
    assert root.status == Status.FAILURE


def test_a_script_at_a_subtree_s_top_is_wrapped_once_by_its_insertion(
        tmp_path: Path, registry: Registry) -> None:
    """A script node is built like any other kind: its insertion's _post runs once a run."""
    root = _load(tmp_path, registry, """format: 1
blackboard:
  count: {type: int, initial: 0}
subtrees:
  Bump:
    root:
      Script: {code: "x := 1"}
root:
  subtree: {tree: Bump, _post: "count += 1"}
""")
    root.tick_once()
    assert root.status == Status.SUCCESS
    assert Blackboard.get("/count") == 1
    assert type(root.decorated).__name__ == "Script"
