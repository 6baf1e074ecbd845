"""BT.CPP XML -> tree file -> BT.CPP XML -> tree file gives the same tree, and BT.CPP loads
the XML each time: several trees, subtrees, port bindings and scaffolded leaves."""

from __future__ import annotations

import subprocess
from pathlib import Path
from typing import Any

import pytest

from interop.test_nav2_navigators import NAVIGATORS, PALETTE
from sar_framework.cli import main
from sar_framework.engine.api import load_spec
from sar_framework.engine.spec import NodeSpec

pytestmark = pytest.mark.timeout(1200)

SEVERAL_TREES = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <ReactiveSequence>
      <Probe target="{goal}" hz="1.5"/>
      <SubTree ID="Approach"/>
      <Fallback>
        <SubTree ID="Approach"/>
        <Report text="done" code="{code}"/>
      </Fallback>
    </ReactiveSequence>
  </BehaviorTree>
  <BehaviorTree ID="Approach">
    <Sequence>
      <Probe target="{goal}" hz="3"/>
      <Inverter><Report text="again" code="{code}"/></Inverter>
    </Sequence>
  </BehaviorTree>
  <TreeNodesModel>
    <Action ID="Report">
      <input_port name="text" type="std::string"/>
      <output_port name="code" type="int"/>
    </Action>
  </TreeNodesModel>
</root>
"""


def shape(node: NodeSpec) -> tuple[Any, ...]:
    """What makes two trees the same: kinds, names, attributes, resolved port bindings."""
    bindings = sorted((name, b.key, repr(b.value)) for name, b in node.bindings.items())
    return (node.kind, node.name, node.subtree, sorted(node.attrs.items()), bindings,
            [shape(child) for child in node.children])


def loaded_by_btcpp(checker: Path, xml: Path) -> None:
    done = subprocess.run([str(checker), str(xml), str(xml.with_suffix(".script")), "0"],
                          capture_output=True, text=True, timeout=60, check=False)
    assert done.returncode == 0, f"BT.CPP refused {xml}:\n{done.stderr}"


def round_trip(xml: Path, tmp_path: Path, checker: Path, capsys: pytest.CaptureFixture[str],
               *extra: str) -> tuple[NodeSpec, NodeSpec]:
    first, again = tmp_path / "first.yaml", tmp_path / "again.yaml"
    exported = tmp_path / "exported.xml"
    assert main(["import", str(xml), "--scaffold", str(tmp_path / "one"), "-o", str(first),
                 *extra]) == 0, capsys.readouterr().err
    assert main(["export", str(first), "-o", str(exported)]) == 0, capsys.readouterr().err
    loaded_by_btcpp(checker, exported)
    assert main(["import", str(exported), "--scaffold", str(tmp_path / "two"), "-o",
                 str(again)]) == 0, capsys.readouterr().err
    return load_spec(first).root, load_spec(again).root


def test_several_trees_with_ports_round_trip(tmp_path: Path, btcpp_checker: Path,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    xml = tmp_path / "several.xml"
    xml.write_text(SEVERAL_TREES)
    first, again = round_trip(xml, tmp_path, btcpp_checker, capsys)
    assert shape(again) == shape(first)
    assert [c.subtree for c in first.children] == [None, "Approach", None]
    exported = (tmp_path / "exported.xml").read_text()
    assert '<BehaviorTree ID="Approach">' in exported
    assert '<output_port name="code" type="int" />' in exported


@pytest.mark.parametrize("xml", NAVIGATORS, ids=[p.stem for p in NAVIGATORS])
def test_nav2_navigator_round_trips(xml: Path, tmp_path: Path, btcpp_checker: Path,
                                    capsys: pytest.CaptureFixture[str]) -> None:
    first, again = round_trip(xml, tmp_path, btcpp_checker, capsys,
                              "--nodes-model", str(PALETTE))
    assert shape(again) == shape(first)
