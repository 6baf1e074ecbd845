"""``sar-tree import``: the file shapes BT.CPP 4.7 accepts, models, entries and scaffolds."""

from __future__ import annotations

import subprocess
import textwrap
from pathlib import Path
from typing import Any

import pytest

from sar_framework.cli import main
from sar_framework.engine.registry import default_registry
from sar_framework.interop.btcpp_file import read_palette
from sar_framework.interop.btcpp_import import ImportResult, import_btcpp
from sar_framework.interop.btcpp_models import port_type
from sar_framework.interop.btcpp_scaffold import scaffold_module
from sar_framework.interop.xml_source import XmlError, parse_xml, read_xml

PALETTE = Path("/work/shared/ros-overlay/src/nav2_behavior_tree/nav2_tree_nodes.xml")


def run(text: str, tmp_path: Path, **kwargs: Any) -> ImportResult:
    xml = tmp_path / "t.xml"
    xml.write_text(textwrap.dedent(text).strip() + "\n")
    return import_btcpp(read_xml(xml), str(xml), default_registry(), **kwargs)


def errors(result: ImportResult, tmp_path: Path) -> list[str]:
    return [str(p).replace(str(tmp_path) + "/", "") for p in result.problems]


TWO_TREES = """
    <root BTCPP_format="4"{main}>
      <BehaviorTree ID="Main">
        <Sequence><Tick/><SubTree ID="Sub"/></Sequence>
      </BehaviorTree>
      <BehaviorTree ID="Sub"><Tick name="Inner"/></BehaviorTree>
    </root>
"""


def test_several_trees_main_tree_to_execute_and_the_others_become_subtrees(
        tmp_path: Path) -> None:
    result = run(TWO_TREES.format(main=' main_tree_to_execute="Main"'), tmp_path)
    assert result.problems == []
    assert result.document == {
        "format": 1, "name": "Main",
        "subtrees": {"Sub": {"Tick": {"name": "Inner"}}},
        "root": {"Sequence": {"children": [{"Tick": {}}, {"subtree": "Sub"}]}},
    }


def test_without_main_tree_to_execute_the_error_lists_the_trees_and_main_picks(
        tmp_path: Path) -> None:
    result = run(TWO_TREES.format(main=""), tmp_path)
    assert errors(result, tmp_path) == [
        "t.xml:1:1: error: which tree is the main one? the file has no main_tree_to_execute; "
        "name one with --main (trees: Main, Sub)"]
    picked = run(TWO_TREES.format(main=""), tmp_path, main="Sub")
    assert picked.problems == [] and picked.document is not None
    assert picked.document["root"] == {"Tick": {"name": "Inner"}}
    missing = run(TWO_TREES.format(main=""), tmp_path, main="Nope")
    assert errors(missing, tmp_path) == ["t.xml:1:1: error: no <BehaviorTree ID=\"Nope\"> "
                                         "(trees: Main, Sub)"]


def test_a_file_without_btcpp_format_and_an_unnamed_tree_reads_as_bt_cpp_reads_it(
        tmp_path: Path) -> None:
    result = run("<root><BehaviorTree><Tick/></BehaviorTree></root>", tmp_path)
    assert result.problems == []
    assert result.document == {"format": 1, "name": "BehaviorTree_0", "root": {"Tick": {}}}


def test_what_tinyxml2_forgives_is_read_and_what_it_does_not_is_located(
        tmp_path: Path) -> None:
    lenient = parse_xml('<root>\n  <BehaviorTree ID="t">\n    <Tick name="a<b"/>\n'
                        '  </BehaviorTree>\n</root>\n<trailing/>\n', "t.xml")
    leaf = lenient.children[0].children[0]
    assert (leaf.attrs["name"], leaf.line, leaf.column) == ("a<b", 3, 5)
    with pytest.raises(XmlError) as caught:
        parse_xml('<root>\n  <BehaviorTree ID="t">\n    <Tick name="a"\n</root>\n', "t.xml")
    assert str(caught.value).startswith("t.xml:4:1: error: XML: ")


def test_includes_are_read_relative_to_the_including_file(tmp_path: Path) -> None:
    (tmp_path / "lib").mkdir()
    (tmp_path / "lib" / "sub.xml").write_text(
        '<root BTCPP_format="4"><BehaviorTree ID="Sub"><Tick name="Inner"/></BehaviorTree>'
        '</root>')
    result = run("""
        <root BTCPP_format="4" main_tree_to_execute="Main">
          <include path="lib/sub.xml"/>
          <include path="lib/missing.xml"/>
          <BehaviorTree ID="Main"><SubTree ID="Sub"/></BehaviorTree>
        </root>
    """, tmp_path)
    assert errors(result, tmp_path) == [
        "t.xml:3:3: error: <include path=\"lib/missing.xml\">: no such file "
        "(lib/missing.xml)"]
    (tmp_path / "lib" / "missing.xml").write_text('<root><include path="../t.xml"/></root>')
    again = import_btcpp(read_xml(tmp_path / "t.xml"), str(tmp_path / "t.xml"),
                         default_registry())
    assert [str(p) for p in again.problems] == [
        f"{tmp_path}/lib/missing.xml:1:7: error: <include path=\"../t.xml\"> includes a file "
        "already read (a cycle)"]


def test_subtree_ports_autoremap_and_model_defaults(tmp_path: Path) -> None:
    result = run("""
        <root main_tree_to_execute="Main">
          <BehaviorTree ID="Main">
            <Sequence>
              <Writer out="{target}"/>
              <SubTree ID="Go" goal="{target}" speed="0.5" _autoremap="true"/>
              <SubTree ID="Go" name="again" goal="{=}" _autoremap="1"/>
            </Sequence>
          </BehaviorTree>
          <BehaviorTree ID="Go"><Mover goal="{goal}" speed="{speed}" map="{map}"/></BehaviorTree>
          <TreeNodesModel>
            <SubTree ID="Go">
              <input_port name="goal"/>
              <input_port name="speed" default="1.0"/>
            </SubTree>
            <Action ID="Writer"><output_port name="out" type="geometry_msgs::msg::Pose"/></Action>
            <Action ID="Mover">
              <input_port name="goal" type="geometry_msgs::msg::Pose"/>
              <input_port name="speed" type="double"/>
              <input_port name="map" type="std::string"/>
            </Action>
          </TreeNodesModel>
        </root>
    """, tmp_path)
    assert result.problems == []
    assert result.document is not None
    children = result.document["root"]["Sequence"]["children"]
    assert children[1:] == [
        {"subtree": {"tree": "Go", "ports": {"goal": "{target}", "speed": 0.5},
                     "autoremap": True}},
        {"subtree": {"tree": "Go", "ports": {"goal": "{=}"}, "autoremap": True}},
    ]
    assert result.document["subtrees"]["Go"]["ports"] == {
        "goal": {"direction": "input", "type": "geometry_msgs/msg/Pose"},
        "speed": {"direction": "input", "type": "float", "default": 1.0}}
    # {map} reaches the main tree through _autoremap, and {speed} where no port gives it
    # (BT.CPP applies a model's default only without _autoremap); {goal} through "{=}";
    # {target} is written by Writer; every entry is declared.
    blackboard = result.document["blackboard"]
    assert list(blackboard) == ["target", "map", "goal", "speed"]
    assert blackboard["goal"]["type"] == "geometry_msgs/msg/Pose"
    assert blackboard["map"] == {"type": "str", "description": "Set by the caller: nothing in "
                                 "t.xml writes it; read by <Mover> port 'map'."}
    assert blackboard["target"]["description"] == ("Written by <Writer> port 'out'; read by "
                                                   "<Mover> port 'goal'.")


def test_a_subtree_without_autoremap_declares_its_private_entries(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    xml = tmp_path / "private.xml"
    xml.write_text('<root main_tree_to_execute="Main"><BehaviorTree ID="Main"><Sequence>'
                   '<Source out="{plan}"/><SubTree ID="Go" path="{plan}"/></Sequence>'
                   '</BehaviorTree><BehaviorTree ID="Go"><Sequence><Smooth in="{path}" '
                   'out="{smooth}"/><Follow path="{smooth}"/></Sequence></BehaviorTree>'
                   '<TreeNodesModel><Action ID="Smooth"><input_port name="in"/><output_port '
                   'name="out"/></Action></TreeNodesModel></root>')
    tree = tmp_path / "private.yaml"
    assert main(["import", str(xml), "--scaffold", str(tmp_path / "leaves"), "-o",
                 str(tree)]) == 0, capsys.readouterr().err
    text = tree.read_text()
    assert "blackboard:\n      smooth: {type: any, description: 'Written by <Smooth> port" in text
    assert "ports:\n      path: {direction: input, type: any}" in text


def test_a_mandatory_subtree_port_left_out_is_refused_as_bt_cpp_refuses_it(
        tmp_path: Path) -> None:
    result = run("""
        <root main_tree_to_execute="Main">
          <BehaviorTree ID="Main"><SubTree ID="Go"/></BehaviorTree>
          <BehaviorTree ID="Go"><Tick/></BehaviorTree>
          <TreeNodesModel><SubTree ID="Go"><input_port name="goal"/></SubTree></TreeNodesModel>
        </root>
    """, tmp_path)
    assert errors(result, tmp_path) == [
        "t.xml:2:27: error: <SubTree ID=\"Go\"> does not remap the port 'goal' its model "
        "declares mandatory (BT.CPP refuses it)"]


def test_unknown_leaves_are_drafted_with_guessed_or_modelled_ports(tmp_path: Path) -> None:
    result = run("""
        <root>
          <BehaviorTree ID="t">
            <Sequence>
              <Probe hz="1" gain="0.5" on="true" label="x" target="{goal}"/>
              <Probe hz="2.5"/>
              <DockRobot max_staging_time="1.5" typo="3"/>
            </Sequence>
          </BehaviorTree>
        </root>
    """, tmp_path, models=read_palette(str(PALETTE))[0])
    assert errors(result, tmp_path) == [
        "t.xml:6:7: error: <DockRobot> has no port 'typo' in its model (nav2_tree_nodes.xml:"
        "265); BT.CPP refuses a port that providedPorts() does not declare"
        .replace("nav2_tree_nodes.xml", str(PALETTE))]
    probe = result.drafts["Probe"]
    assert probe.guessed == {"hz": ("input", "float"), "gain": ("input", "float"),
                             "on": ("input", "bool"), "label": ("input", "str"),
                             "target": ("inout", "any")}
    assert result.drafts["DockRobot"].model is not None
    fixed = run("""
        <root><BehaviorTree ID="t"><Sequence>
          <Probe hz="1" target="{goal}"/><Probe hz="2.5"/><DockRobot max_staging_time="1.5"/>
        </Sequence></BehaviorTree></root>
    """, tmp_path, models=read_palette(str(PALETTE))[0])
    assert fixed.document is not None
    children = fixed.document["root"]["Sequence"]["children"]
    assert children == [{"Probe": {"hz": 1.0, "target": "{goal}"}}, {"Probe": {"hz": 2.5}},
                        {"DockRobot": {"max_staging_time": 1.5}}]
    text = scaffold_module(list(fixed.drafts.values()), "t.xml")
    compile(text, "leaves.py", "exec")
    assert "BidirectionalPort('target', 'any', default='{=}', description='Guessed" in text
    assert ("InputPort('max_staging_time', float, default=1000.0, description='Maximum time"
            in text)
    assert "OutputPort('error_code_id', int" in text
    assert 'return Status.FAILURE' in text


def test_a_control_node_nobody_maps_is_refused_with_its_model_category(
        tmp_path: Path) -> None:
    result = run("""
        <root><BehaviorTree ID="t"><Sequence><Mystery><Tick/></Mystery></Sequence>
        </BehaviorTree></root>
    """, tmp_path)
    assert errors(result, tmp_path) == [
        "t.xml:1:38: error: <Mystery> is a node with children this framework has no kind for; "
        "only unknown leaves can be scaffolded (see docs/reference/btcpp-interop.md)"]


def test_palette_models_carry_types_defaults_and_directions() -> None:
    models, problems = read_palette(str(PALETTE))
    assert problems == []
    compute = models["ComputePathToPose"]
    assert compute.category == "Action"
    goal, path = compute.port("goal"), compute.port("path")
    assert goal is not None and path is not None
    assert (goal.direction, goal.type) == ("input", "geometry_msgs/msg/PoseStamped")
    assert (path.direction, path.type) == ("output", "nav_msgs/msg/Path")
    assert models["RecoveryNode"].port("number_of_retries").default == "1"  # type: ignore[union-attr]
    assert [port_type(t) for t in ("double", "uint16", "chrono::milliseconds", "string",
                                   "vector<int>", "Whatever")] == [
        "float", "int", "int", "str", "list", "any"]


def test_scaffold_writes_a_plugin_the_imported_tree_validates_with(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    xml = tmp_path / "probe.xml"
    xml.write_text('<root><BehaviorTree ID="t"><Sequence><Probe hz="1" target="{goal}"/>'
                   '<Probe hz="2.5" out="{goal}"/></Sequence></BehaviorTree></root>')
    out = tmp_path / "probe.yaml"
    assert main(["import", str(xml), "--scaffold", str(tmp_path / "leaves"), "-o",
                 str(out)]) == 0, capsys.readouterr().err
    assert (tmp_path / "leaves" / "probe_leaves.py").is_file()
    assert "plugins: [leaves/probe_leaves.py]\n" in out.read_text()
    assert main(["validate", str(out)]) == 0, capsys.readouterr().err


SUBTREE_HEADER = Path("/work/shared/ros-overlay/src/behaviortree_cpp/include/behaviortree_cpp/"
                      "decorators/subtree_node.h")


def btcpp_subtree_example(tmp_path: Path) -> Path:
    """BT.CPP 4.7.3's own SubTree example (the XML in subtree_node.h's comment)."""
    text = SUBTREE_HEADER.read_text()
    xml = tmp_path / "subtree_example.xml"
    xml.write_text(text[text.index("<root"):text.index("</root>") + len("</root>")] + "\n")
    return xml


def test_btcpp_subtree_example_imports(tmp_path: Path) -> None:
    xml = btcpp_subtree_example(tmp_path)
    result = import_btcpp(read_xml(xml), str(xml), default_registry())
    assert result.problems == []
    assert result.document is not None
    children = result.document["root"]["Sequence"]["children"]
    assert children[1] == {"subtree": {"tree": "Talk", "ports": {"param": "{myParam}"}}}
    assert children[4] == {"subtree": {"tree": "Talk", "autoremap": True}}
    assert children[0] == {"Script": {"code": "myParam='Hello'"}}


def test_btcpp_subtree_example_validates_and_exports_what_btcpp_loads(
        tmp_path: Path, btcpp_checker: Path, capsys: pytest.CaptureFixture[str]) -> None:
    xml = btcpp_subtree_example(tmp_path)
    tree, back = tmp_path / "example.yaml", tmp_path / "back.xml"
    assert main(["import", str(xml), "--scaffold", str(tmp_path / "leaves"), "-o",
                 str(tree)]) == 0, capsys.readouterr().err
    assert main(["validate", str(tree)]) == 0, capsys.readouterr().err
    assert main(["export", str(tree), "-o", str(back)]) == 0, capsys.readouterr().err
    text = back.read_text()
    for line in ('<Script name="Script" code="myParam=\'Hello\'" />',
                 '<SubTree ID="Talk" param="{myParam}" />', '<SubTree ID="Talk" param="World" />',
                 '<SubTree ID="Talk" _autoremap="true" />'):
        assert line in text, text
    done = subprocess.run([str(btcpp_checker), str(back), str(tmp_path / "none"), "0"],
                          capture_output=True, text=True, timeout=60, check=False)
    assert done.returncode == 0, done.stderr


def test_subtree_ports_survive_import_and_export(tmp_path: Path,
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    xml = tmp_path / "ports.xml"
    xml.write_text('<root main_tree_to_execute="Main"><BehaviorTree ID="Main"><Sequence>'
                   '<Writer out="{target}"/><SubTree ID="Go" goal="{target}" _autoremap="true"/>'
                   '</Sequence></BehaviorTree><BehaviorTree ID="Go"><Mover goal="{goal}"/>'
                   '</BehaviorTree></root>')
    tree, back = tmp_path / "ports.yaml", tmp_path / "back.xml"
    assert main(["import", str(xml), "--scaffold", str(tmp_path / "leaves"), "-o",
                 str(tree)]) == 0, capsys.readouterr().err
    assert main(["export", str(tree), "-o", str(back)]) == 0, capsys.readouterr().err
    assert '<SubTree ID="Go" goal="{target}" _autoremap="true"' in back.read_text()


def test_without_scaffold_unknown_leaves_are_warnings_and_the_tree_is_still_checked(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    xml = tmp_path / "probe.xml"
    xml.write_text('<root><BehaviorTree ID="t"><Sequence>\n<Probe hz="1"/>\n'
                   '<Dwell duration="{n}"/></Sequence></BehaviorTree></root>')
    assert main(["import", str(xml)]) == 1
    assert "'duration' of <Dwell> is a param, not a port" in capsys.readouterr().err
    xml.write_text('<root><BehaviorTree ID="t">\n<Probe hz="1"/></BehaviorTree></root>')
    assert main(["import", str(xml), "-o", str(tmp_path / "probe.yaml")]) == 0
    err = capsys.readouterr().err
    assert f"{xml}:2:1: warning: no plugin provides <Probe>; --scaffold DIR writes one" in err
    assert "plugins" not in (tmp_path / "probe.yaml").read_text()


@pytest.mark.parametrize(("xml", "message"), [
    ('<root main_tree_to_execute="A"><BehaviorTree ID="A"><Tick/></BehaviorTree>'
     '<BehaviorTree ID="B"><Tick/></BehaviorTree></root>',
     "t.xml:1:1: error: --main B, but the file says main_tree_to_execute=\"A\""),
    ('<root><BehaviorTree ID="A"><Tick/></BehaviorTree><BehaviorTree ID="A"><Tick/>'
     '</BehaviorTree></root>', "t.xml:1:50: error: a second <BehaviorTree ID=\"A\"> (the first "
     "is at "),
    ('<root><BehaviorTree ID="A"><Tick/></BehaviorTree><TreeNodesModel/><TreeNodesModel/>'
     '</root>', "t.xml:1:67: error: a second <TreeNodesModel> (BT.CPP: 'Only a single node"),
    ('<root><BehaviorTree ID="A"><Tick/></BehaviorTree><Junk/></root>',
     "t.xml:1:50: error: unexpected <Junk> under <root>"),
    ('<root><include/><BehaviorTree ID="A"><Tick/></BehaviorTree></root>',
     "t.xml:1:7: error: <include> needs a path"),
    ('<root><include path="x.xml" ros_pkg="no_such_pkg"/><BehaviorTree ID="A"><Tick/>'
     '</BehaviorTree></root>', "t.xml:1:7: error: <include ros_pkg=\"no_such_pkg\">: no "
     "share/no_such_pkg under $AMENT_PREFIX_PATH"),
])
def test_file_shape_problems_name_their_place(xml: str, message: str, tmp_path: Path) -> None:
    result = run(xml, tmp_path, main="B")
    assert any(line.startswith(message) for line in errors(result, tmp_path)), \
        errors(result, tmp_path)


def test_scaffold_never_overwrites_a_module_that_differs(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    xml = tmp_path / "probe.xml"
    xml.write_text('<root><BehaviorTree ID="t"><Probe hz="1"/></BehaviorTree></root>')
    args = ["import", str(xml), "--scaffold", str(tmp_path / "leaves"), "-o",
            str(tmp_path / "probe.yaml")]
    assert main(args) == 0
    assert main(args) == 0  # the same scaffold again: nothing lost
    module = tmp_path / "leaves" / "probe_leaves.py"
    module.write_text(module.read_text().replace("return Status.FAILURE",
                                                 "return Status.SUCCESS"))
    capsys.readouterr()
    assert main(args) == 1
    assert capsys.readouterr().err == (f"sar-tree: error: {module} exists and differs from the "
                                       "scaffold (it may hold your code): move it, or choose "
                                       "another --scaffold DIR\n")
    assert "return Status.SUCCESS" in module.read_text()
