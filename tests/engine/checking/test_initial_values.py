"""Initial values from outside the file: converted to the declared type, or located."""

from __future__ import annotations

import re
from pathlib import Path

import py_trees
import pytest

from sar_framework.engine.api import TreeLoadError, load_tree, validate
from sar_framework.engine.checking.initial_values import SetError, parse_settings

TREE = """\
format: 1
name: t
blackboard:
  battery: {type: float, initial: 60.0}
  armed: {type: bool, initial: false}
  stops: {type: list}
  goal: {type: geometry_msgs/msg/PoseStamped}
root:
  Script: {code: "battery := battery - 1"}
"""


@pytest.fixture
def tree(tmp_path: Path) -> Path:
    path = tmp_path / "t.yaml"
    path.write_text(TREE)
    return path


def test_values_are_read_as_yaml() -> None:
    assert parse_settings(["battery=50", "armed=true", "stops=[a, b]", "name='50'",
                           "empty="]) == {"battery": 50, "armed": True, "stops": ["a", "b"],
                                          "name": "50", "empty": ""}


@pytest.mark.parametrize("text", ["battery", "=3", "x=[1,"])
def test_a_text_that_is_not_name_equals_value_is_refused(text: str) -> None:
    with pytest.raises(SetError, match=re.escape(f"--set '{text}'")):
        parse_settings([text])


def test_a_set_value_replaces_the_files_and_is_written_before_the_first_tick(
        tree: Path) -> None:
    loaded = load_tree(tree, initial_values=parse_settings(["battery=50", "stops=a;b"]))
    try:
        assert py_trees.blackboard.Blackboard.get("/battery") == 50.0
        assert py_trees.blackboard.Blackboard.get("/stops") == ["a", "b"]
        assert loaded.spec.declarations[""]["battery"].initial == 50.0
        loaded.root.tick_once()
        assert py_trees.blackboard.Blackboard.get("/battery") == 49.0
    finally:
        py_trees.blackboard.Blackboard.clear()


def test_a_wrong_type_is_located_at_the_declaration(tree: Path) -> None:
    result = validate(tree, initial_values={"armed": "maybe"})
    assert result.spec is None
    assert [str(d) for d in result.diagnostics] == [
        f"{tree}:5:3: error: --set armed=maybe: expected a bool (true/false/1/0), got "
        "'maybe' (the entry is declared here as bool)"]


@pytest.mark.ros  # a message literal: the .msg files of the ROS interfaces
def test_a_message_entry_takes_a_literal(tree: Path) -> None:
    result = validate(tree, initial_values={"goal": "1;2;0"})
    assert result.ok, [str(d) for d in result.diagnostics]
    goal = result.spec.entries["/goal"].initial  # type: ignore[union-attr]
    assert goal.fields["pose"]["position"] == {"x": 1.0, "y": 2.0, "z": 0.0}
    result = validate(tree, initial_values={"goal": {"x": 1, "yew": 0}})
    assert f"{tree}:7:3: error: --set goal={{'x': 1, 'yew': 0}}: yew: not a key" in str(
        result.diagnostics[0])


def test_an_unknown_entry_gets_a_did_you_mean(tree: Path) -> None:
    with pytest.raises(TreeLoadError, match=r"no entry 'batery' \(did you mean 'battery'\?\)"):
        load_tree(tree, initial_values={"batery": 5})


def test_an_unknown_entry_is_located_at_the_blackboard_section_and_named_as_given(
        tree: Path) -> None:
    result = validate(tree, initial_values={"batery": 5})
    assert [str(d) for d in result.diagnostics] == [
        f"{tree}:3:1: error: --set batery=5 (command-line argument): the tree declares no "
        "entry 'batery' (did you mean 'battery'?) in its 'blackboard:' section (declared: "
        "battery, armed, stops, goal)"]


def test_an_unknown_entry_of_a_tree_without_a_blackboard_section_says_so(
        tmp_path: Path) -> None:
    path = tmp_path / "bare.yaml"
    path.write_text("format: 1\nname: bare\nroot:\n  AlwaysSuccess: {}\n")
    result = validate(path, initial_values={"battery": [1, 2]})
    assert [str(d) for d in result.diagnostics] == [
        f"{path}:1:1: error: --set battery=[1, 2] (command-line argument): the tree declares "
        "no entry 'battery': it has no 'blackboard:' section"]
