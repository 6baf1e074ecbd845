"""Pose literals through XML: BT.CPP's text forms import, and a literal exports as Nav2's."""

from __future__ import annotations

from pathlib import Path

import pytest

from sar_framework.cli import main
from sar_framework.engine.api import validate
from sar_framework.engine.message_literals import MessageLiteral

XML = """\
<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <NavigateToPose name="Short" goal="1.0;2.0;0.0"/>
      <NavigateToPose name="Nav2s" goal="0;odom;3.0;4.0;0.0;0;0;0;1"/>
    </Sequence>
  </BehaviorTree>
</root>
"""
TREE = """\
format: 1
name: main
root:
  NavigateToPose: {goal: {x: 1.0, y: 2.0, yaw: 0.0}}
"""


def goals(tree: Path) -> list[MessageLiteral]:
    result = validate(tree)
    assert result.ok and result.spec is not None, [str(d) for d in result.diagnostics]
    return [n.bindings["goal"].value for n in result.spec.nodes() if n.kind == "NavigateToPose"]


def test_an_imported_text_form_is_a_pose_literal(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "t.xml").write_text(XML)
    assert main(["import", str(tmp_path / "t.xml"), "-o", str(tmp_path / "t.yaml")]) == 0, (
        capsys.readouterr().err)
    short, nav2s = goals(tmp_path / "t.yaml")
    assert short.fields["header"] == {"frame_id": "map", "stamp": "now"}
    assert short.fields["pose"]["position"] == {"x": 1.0, "y": 2.0, "z": 0.0}
    assert nav2s.fields["header"] == {"stamp": {"sec": 0, "nanosec": 0}, "frame_id": "odom"}


def test_a_literal_exports_as_nav2s_text_and_comes_back(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "t.yaml").write_text(TREE)
    assert main(["export", str(tmp_path / "t.yaml"), "-o", str(tmp_path / "t.xml")]) == 0, (
        capsys.readouterr().err)
    assert 'goal="0;map;1.0;2.0;0.0;0.0;0.0;0.0;1.0"' in (tmp_path / "t.xml").read_text()
    assert main(["import", str(tmp_path / "t.xml"), "-o", str(tmp_path / "back.yaml")]) == 0, (
        capsys.readouterr().err)
    (back,) = goals(tmp_path / "back.yaml")
    assert back.fields["pose"] == goals(tmp_path / "t.yaml")[0].fields["pose"]


def test_an_initial_pose_exports_as_a_script_of_nav2s_text(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "t.yaml").write_text(
        "format: 1\nname: main\nblackboard:\n"
        "  home: {type: geometry_msgs/msg/PoseStamped, initial: {x: 1.0, y: 2.0, yaw: 0.0}}\n"
        "root:\n  NavigateToPose: {goal: '{home}'}\n")
    assert main(["export", str(tmp_path / "t.yaml"), "-o", str(tmp_path / "t.xml")]) == 0, (
        capsys.readouterr().err)
    assert "home := '0;map;1.0;2.0;0.0;0.0;0.0;0.0;1.0'" in (tmp_path / "t.xml").read_text()
    assert main(["import", str(tmp_path / "t.xml"), "-o", str(tmp_path / "back.yaml")]) == 0, (
        capsys.readouterr().err)
    result = validate(tmp_path / "back.yaml")
    assert result.ok and result.spec is not None, [str(d) for d in result.diagnostics]
    assert result.spec.entries["/home"].initial.fields["pose"]["position"] == {
        "x": 1.0, "y": 2.0, "z": 0.0}


def test_a_scaffolded_leaf_keeps_a_models_pose_default_as_text(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "t.xml").write_text("""\
<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main"><Park/></BehaviorTree>
  <TreeNodesModel>
    <Action ID="Park">
      <input_port name="spot" type="geometry_msgs::msg::PoseStamped" default="1.0;2.0;0.0"/>
    </Action>
  </TreeNodesModel>
</root>
""")
    assert main(["import", str(tmp_path / "t.xml"), "--scaffold", str(tmp_path / "leaves"),
                 "-o", str(tmp_path / "t.yaml")]) == 0, capsys.readouterr().err
    source = (tmp_path / "leaves" / "t_leaves.py").read_text()
    assert "InputPort('spot', 'geometry_msgs/msg/PoseStamped', default='1.0;2.0;0.0'" in source
    result = validate(tmp_path / "t.yaml")
    assert result.ok and result.spec is not None, [str(d) for d in result.diagnostics]
    (park,) = [n for n in result.spec.nodes() if n.kind == "Park"]
    assert park.bindings["spot"].value.fields["pose"]["position"]["y"] == 2.0
