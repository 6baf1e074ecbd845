"""``sar-tree import``: BT.CPP 4 XML to our format, round trips and file:line diagnostics."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from sar_framework.cli import main
from sar_framework.engine.api import load_spec
from sar_framework.engine.nodes.node_kinds import PY_TREES_KINDS
from sar_framework.engine.registry import default_registry, extend
from sar_framework.engine.spec import NodeSpec, TreeSpec
from sar_framework.interop.btcpp_import import import_btcpp
from sar_framework.interop.xml_source import parse_xml

REPO = Path(__file__).resolve().parents[2]
TUTORIAL_PLUGINS = REPO / "trees" / "tutorials" / "plugins" / "tutorial_leaves.py"
FIXTURES = Path(__file__).parent / "fixtures"
TREES = [REPO / "trees" / "search_and_rescue.yaml",
         *sorted((REPO / "trees" / "tutorials").glob("0*.yaml")),
         *sorted((REPO / "trees" / "examples").glob("*.yaml"))]


def shape(node: NodeSpec) -> tuple[Any, ...]:
    """Everything that makes two trees tick alike, recursively."""
    return (node.kind, node.name, node.id, node.subtree, sorted(node.attrs.items()),
            [shape(child) for child in node.children])


def declarations(spec: TreeSpec) -> dict[str, list[tuple[Any, ...]]]:
    """Each scope's ``blackboard:`` section: (name, type, initial, description) in order."""
    return {scope: [(d.name, d.type, d.initial, d.description) for d in declared.values()]
            for scope, declared in spec.declarations.items() if declared}


@pytest.mark.parametrize("tree", TREES, ids=[p.name for p in TREES])
def test_yaml_to_xml_to_yaml_gives_the_same_tree(tree: Path, tmp_path: Path,
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    """Leaves and BT.CPP kinds come back as they were; a py_trees kind with a BT.CPP twin
    (``sequence``, ``retry``...) comes back as that BT.CPP kind: the XML is a fixed point."""
    xml, back, again = tmp_path / "tree.xml", tmp_path / "back.yaml", tmp_path / "again.xml"
    plugins = ["--plugin-path", str(TUTORIAL_PLUGINS.parent)]  # every tutorial plugin
    assert main(["export", str(tree), "-o", str(xml), *plugins]) == 0
    assert main(["import", str(xml), "-o", str(back), *plugins]) == 0, capsys.readouterr().err
    assert main(["export", str(back), "-o", str(again), *plugins]) == 0
    assert again.read_text() == xml.read_text()
    original, loaded = load_spec(tree), load_spec(back)
    assert (loaded.name, loaded.description) == (original.name, original.description)
    assert declarations(loaded) == declarations(original)
    if not any(n.kind in PY_TREES_KINDS for n in original.nodes()):
        assert shape(loaded.root) == shape(original.root)


def test_bt_cpp_kinds_round_trip_one_to_one(tmp_path: Path) -> None:
    tree = tmp_path / "controls.yaml"
    tree.write_text(CONTROLS_TREE)
    xml, back = tmp_path / "tree.xml", tmp_path / "back.yaml"
    plugins = ["--plugin-path", str(TUTORIAL_PLUGINS)]
    assert main(["export", str(tree), "-o", str(xml), *plugins]) == 0
    text = xml.read_text()
    for tag in ("<SequenceWithMemory", "<Parallel", 'success_count="-2"', "<Switch3",
                'variable="{mode}"', "<RecoveryNode", "<Control ID=\"RecoveryNode\"",
                "<RateController", "<SetBlackboard", 'then_skip="false"', "<Sleep"):
        assert tag in text, tag
    assert main(["import", str(xml), "-o", str(back), *plugins]) == 0
    paths = [TUTORIAL_PLUGINS]
    assert (shape(load_spec(back, plugin_paths=paths).root)
            == shape(load_spec(tree, plugin_paths=paths).root))


CONTROLS_TREE = """\
format: 1
name: controls
root:
  SequenceWithMemory:
    children:
      - SetBlackboard: {value: "2", output_key: mode}
      - Parallel:
          success_count: -2
          children: [AlwaysSuccess: {}, Countdown: {ticks: 2}, AlwaysFailure: {}]
      - Switch3:
          variable: "{mode}"
          case_1: "1"
          case_2: "2"
          case_3: three
          children: [Countdown: {}, Sleep: {msec: 5}, AlwaysSuccess: {}, AlwaysFailure: {}]
      - RecoveryNode:
          number_of_retries: 2
          children:
            - RateController: {hz: 2.5, child: {Countdown: {}}}
            - RunOnce: {then_skip: false, child: {Countdown: {}}}
      - WhileDoElse:
          children: [AlwaysSuccess: {}, Delay: {delay_msec: 10, child: {Countdown: {}}}]
"""


def problems(text: str) -> list[str]:
    registry = extend(default_registry().copy(), [str(TUTORIAL_PLUGINS)])
    result = import_btcpp(parse_xml(text, "t.xml"), "t.xml", registry)
    assert result.document is None
    return [str(p) for p in result.problems]


def test_nav2_navigator_shape_imports_with_its_leaves_as_our_nav2_leaves(
        capsys: pytest.CaptureFixture[str]) -> None:
    """Before sar_plugins.nav2, its five Nav2 leaves were drafted (no plugin provided them)."""
    assert main(["import", str(FIXTURES / "nav2_navigator_shape.xml")]) == 0
    captured = capsys.readouterr()
    where = str(FIXTURES / "nav2_navigator_shape.xml")
    assert not [line for line in captured.err.splitlines() if line.startswith(f"{where}:")]
    for tag in ("ComputePathToPose", "FollowPath", "GoalUpdated", "ClearEntireCostmap", "Spin"):
        assert f"{tag}:" in captured.out


def test_bad_params_point_at_their_lines_and_an_unknown_leaf_is_no_problem() -> None:
    text = ('<root BTCPP_format="4">\n  <BehaviorTree ID="t">\n    <Sequence>\n'
            '      <Countdon ticks="2"/>\n      <Countdown ticks="two"/>\n'
            '      <Countdown tiks="2"/>\n    </Sequence>\n  </BehaviorTree>\n</root>\n')
    assert problems(text) == [
        "t.xml:5:7: error: 'ticks' must be a integer, got 'two'",
        "t.xml:6:7: error: <Countdown> has no param or port 'tiks' (it has: ticks, result)",
    ]


@pytest.mark.parametrize(("xml", "message"), [
    ('<root BTCPP_format="3"><BehaviorTree ID="t"><Countdown/></BehaviorTree></root>',
     "t.xml:1:1: error: BTCPP_format=\"3\": only BehaviorTree.CPP 4 files are read"),
    ('<root BTCPP_format="4"><BehaviorTree ID="a"><Countdown/></BehaviorTree>'
     '<BehaviorTree ID="b"><Countdown/></BehaviorTree></root>',
     "t.xml:1:1: error: which tree is the main one?"),
    ('<root BTCPP_format="4"><BehaviorTree ID="t"><Script code="x:=1 +"/>'
     '</BehaviorTree></root>', "t.xml:1:45: error: script 'code' of <Script>: "),
    ('<root BTCPP_format="4"><BehaviorTree ID="t"><Precondition if="a &lt;&gt; 2">'
     '<Countdown/></Precondition></BehaviorTree></root>',
     "t.xml:1:45: error: script 'if' of <Precondition>: "),
    ('<root BTCPP_format="4"><BehaviorTree ID="t"><Repeat><Countdown/></Repeat>'
     '</BehaviorTree></root>', "t.xml:1:45: error: <Repeat>: needs the port 'num_cycles'"),
    ('<root BTCPP_format="4"><BehaviorTree ID="t"><Delay delay_msec="soon"><Countdown/>'
     '</Delay></BehaviorTree></root>',
     "t.xml:1:45: error: <Delay>: 'delay_msec' must be a integer, got 'soon'"),
    ('<root BTCPP_format="4"><BehaviorTree ID="t"><Sleep msec="1" ms="2"/>'
     '</BehaviorTree></root>', "t.xml:1:45: error: <Sleep>: no port 'ms' (its ports: msec)"),
    ('<root BTCPP_format="4"><BehaviorTree ID="t"><AlwaysSuccess><Countdown/></AlwaysSuccess>'
     '</BehaviorTree></root>', "t.xml:1:45: error: <AlwaysSuccess> is a leaf"),
    ('<root BTCPP_format="4"><BehaviorTree ID="t"><Repeat num_cycles="twice"><Countdown/>'
     '</Repeat></BehaviorTree></root>', "t.xml:1:45: error: <Repeat>: 'num_cycles' must be a "
     "integer, got 'twice'"),
    ('<root BTCPP_format="4"><BehaviorTree ID="t"><Inverter><Countdown/><Countdown/>'
     '</Inverter></BehaviorTree></root>', "t.xml:1:45: error: <Inverter> is a decorator"),
    ('<root BTCPP_format="4"><BehaviorTree ID="t"><SubTree ID="x" goal="{goal}"/>'
     '</BehaviorTree></root>', "t.xml:1:45: error: <SubTree ID=\"x\">: no <BehaviorTree"),
    ('<root BTCPP_format="4"><BehaviorTree ID="t"><RateController hz="{hz}"><Countdown/>'
     '</RateController></BehaviorTree></root>', "t.xml:1:45: error: port 'hz' of "
     "<RateController> reads the blackboard entry '{hz}'; ours takes a fixed value here"),
    ('<root BTCPP_format="4"><BehaviorTree ID="t"><Countdown ticks="{n}"/></BehaviorTree>'
     '</root>', "t.xml:1:45: error: 'ticks' of <Countdown> is a param, not a port"),
    ('<root BTCPP_format="4"><BehaviorTree ID="t"><Countdown _skipIf="a ="/>'
     '</BehaviorTree></root>', "t.xml:1:45: error: script '_skipIf' of <Countdown>: "),
    ('<root main_tree_to_execute="t"><BehaviorTree ID="t"><SubTree ID="s" _skipIf="a ="/>'
     '</BehaviorTree><BehaviorTree ID="s"><Countdown/></BehaviorTree></root>',
     "t.xml:1:53: error: script '_skipIf' of <SubTree>: "),
])
def test_what_cannot_be_imported_is_named(xml: str, message: str) -> None:
    assert problems(xml)[0].startswith(message)


def test_entries_on_control_ports_and_subtree_conditions_import() -> None:
    registry = extend(default_registry().copy(), [str(TUTORIAL_PLUGINS)])
    text = ('<root main_tree_to_execute="t"><BehaviorTree ID="t"><Sequence>'
            '<Script code="t := 450; n := 2"/>'
            '<Timeout msec="{t}"><Repeat num_cycles="{n}"><Countdown/></Repeat></Timeout>'
            '<SubTree ID="s" _skipIf="n == 2" _post="t := 0"/>'
            '</Sequence></BehaviorTree><BehaviorTree ID="s"><Countdown/></BehaviorTree></root>')
    result = import_btcpp(parse_xml(text, "t.xml"), "t.xml", registry)
    assert result.problems == []
    children = result.document["root"]["Sequence"]["children"]
    assert children[1]["Timeout"]["msec"] == "{t}"
    assert children[1]["Timeout"]["child"]["Repeat"]["num_cycles"] == "{n}"
    assert children[2] == {"subtree": {"tree": "s", "_skipIf": "n == 2", "_post": "t := 0"}}


def test_malformed_xml_is_a_located_error(tmp_path: Path,
                                          capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "bad.xml"
    bad.write_text('<root BTCPP_format="4">\n  <BehaviorTree ID="t">\n</root>\n')
    assert main(["import", str(bad)]) == 1
    assert capsys.readouterr().err == f"{bad}:3:3: error: XML: mismatched tag\n"


def test_our_validator_checks_what_the_importer_cannot(tmp_path: Path,
                                                       capsys: pytest.CaptureFixture[str]) -> None:
    xml = tmp_path / "refs.xml"
    xml.write_text('<root BTCPP_format="4"><BehaviorTree ID="t">'
                   '<ReportId taker="nobody"/></BehaviorTree></root>')
    out = tmp_path / "refs.yaml"
    assert main(["import", str(xml), "-o", str(out), "--plugin-path",
                 str(TUTORIAL_PLUGINS)]) == 1
    err = capsys.readouterr().err
    assert f"{out}:" in err and "'taker' names no leaf" in err, err
    assert not out.exists()


def test_explicit_v3_style_elements_and_custom_nodes_are_read() -> None:
    text = ('<root BTCPP_format="4"><BehaviorTree ID="t">'
            '<SarParallel name="Both" policy="success_on_selected" selected="A;B" '
            'synchronise="false"><Action ID="Countdown" name="A" ticks="3"/>'
            '<SarOneShot policy="on_successful_completion"><Countdown name="B"/></SarOneShot>'
            '<Timeout msec="2500"><Countdown name="C" result="failure"/></Timeout>'
            '</SarParallel></BehaviorTree>'
            '<TreeNodesModel><Action ID="Countdown"/></TreeNodesModel></root>')
    registry = extend(default_registry().copy(), [str(TUTORIAL_PLUGINS)])
    result = import_btcpp(parse_xml(text, "t.xml"), "t.xml", registry)
    assert result.problems == []
    assert result.document == {"format": 1, "name": "t", "root": {"parallel": {
        "name": "Both", "policy": "success_on_selected", "synchronise": False,
        "selected": ["A", "B"], "children": [
            {"Countdown": {"name": "A", "ticks": 3}},
            {"one_shot": {"policy": "on_successful_completion",
                          "child": {"Countdown": {"name": "B"}}}},
            {"Timeout": {"msec": 2500, "child": {"Countdown": {"name": "C",
                                                               "result": "failure"}}}},
        ]}}}


def test_an_unknown_xml_node_close_to_a_plugin_gets_a_did_you_mean(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Regression: <NavigateToZon> was drafted with no did-you-mean."""
    xml = tmp_path / "typo.xml"
    xml.write_text('<root BTCPP_format="4" main_tree_to_execute="M">\n'
                   '  <BehaviorTree ID="M">\n    <Sequence>\n      <NavigateToZon/>\n'
                   '    </Sequence>\n  </BehaviorTree>\n</root>\n')
    assert main(["import", str(xml), "-o", str(tmp_path / "typo.yaml")]) == 0
    assert (f"{xml}:4:7: warning: no plugin provides <NavigateToZon> (did you mean "
            "'NavigateToZone'?); --scaffold DIR writes one to fill in") in capsys.readouterr().err


def test_export_usage_and_input_errors(tmp_path: Path,
                                       capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["export", str(tmp_path / "missing.yaml")]) == 2
    assert "no such file" in capsys.readouterr().err
    bad = tmp_path / "bad.yaml"
    bad.write_text("format: 1\nroot:\n  sequence: {children: [{Nope: {}}]}\n")
    assert main(["export", str(bad)]) == 1
    err = capsys.readouterr().err
    assert f"{bad}:3:" in err and "unknown plugin 'Nope'" in err, err


def test_a_kind_s_other_btcpp_id_imports_as_that_kind(tmp_path: Path) -> None:
    """SequenceStar (BT.CPP 3's name) is declared a spelling of SequenceWithMemory."""
    xml, back = tmp_path / "old.xml", tmp_path / "back.yaml"
    xml.write_text('<root BTCPP_format="4"><BehaviorTree ID="Main"><SequenceStar>'
                   "<AlwaysSuccess/><AlwaysFailure/></SequenceStar></BehaviorTree></root>")
    assert main(["import", str(xml), "-o", str(back)]) == 0
    assert load_spec(back).root.kind == "SequenceWithMemory"
