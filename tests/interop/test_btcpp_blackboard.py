"""The ``blackboard:`` section in BT.CPP XML: initial values BT.CPP runs with, declarations
a re-import gives back, and ``{=}`` on import (see ``sar_framework/interop/btcpp_blackboard``).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from interop.scripted import compare
from sar_framework.cli import main
from sar_framework.engine.api import load_spec
from sar_framework.engine.registry import Registry, default_registry, extend
from sar_framework.engine.spec import TreeSpec
from sar_framework.interop.btcpp_blackboard import parse_initial, unwrap_initial
from sar_framework.interop.btcpp_export import export_btcpp
from sar_framework.interop.btcpp_import import import_btcpp
from sar_framework.interop.xml_source import parse_xml

REPO = Path(__file__).resolve().parents[2]
GENERIC = REPO / "tests" / "engine" / "plugins_for_tests" / "generic"
PORT_LEAVES = REPO / "trees" / "tutorials" / "plugins" / "port_leaves.py"

#: Initial values of each type (a text with a quote), a caller input, and a subtree with a
#: private counter inserted twice, once inside a Repeat: BT.CPP must set ``n`` once per
#: insertion, as our loader does, so each insertion's first round alone is "FirstVisit".
INITIAL_TREE = """\
format: 1
name: initial_values
blackboard:
  limit: {type: int, initial: 2, description: Rounds to run.}
  rate: {type: float, initial: 0.5}
  armed: {type: bool, initial: true, description: Whether to act.}
  label: {type: str, initial: "it's ok", description: A text with a quote.}
  zones: {type: list, initial: [a, b]}
  rounds: {type: int, initial: 0}
  goal: {type: int, description: Set by the caller.}
root:
  Sequence:
    children:
      - Repeat:
          num_cycles: 2
          child: {subtree: Round}
      - subtree: Round
      - ScriptCondition: {name: Checked, code: "armed && rate == 0.5 && label == \\"it's ok\\""}
      - ScriptCondition: {name: Counted, code: "rounds == limit + 1"}
      - Tick: {name: Done}
subtrees:
  Round:
    blackboard:
      n: {type: int, initial: 0, description: Visits of this insertion.}
    root:
      Sequence:
        children:
          - Script: {name: Bump, code: "n += 1; @rounds += 1"}
          - Fallback:
              children:
                - Sequence:
                    children:
                      - ScriptCondition: {name: First, code: "n == 1"}
                      - Tick: {name: FirstVisit}
                - Tick: {name: LaterVisit}
"""


def registry() -> Registry:
    """The built-in leaves and the generic test leaves (``Tick``)."""
    return extend(default_registry().copy(), [str(GENERIC)])


def declarations(spec: TreeSpec) -> dict[str, list[tuple[Any, ...]]]:
    """Each scope's section: (name, type, initial, description), in order."""
    return {scope: [(d.name, d.type, d.initial, d.description) for d in declared.values()]
            for scope, declared in spec.declarations.items() if declared}


def test_initial_values_tick_as_in_btcpp(btcpp_checker: Path, tmp_path: Path) -> None:
    tree = tmp_path / "initial_values.yaml"
    tree.write_text(INITIAL_TREE)
    ours = compare(tree, registry(), btcpp_checker, {})
    assert [line for line in ours if line.startswith("visit")] == [
        "visit FirstVisit SUCCESS", "visit LaterVisit SUCCESS", "visit FirstVisit SUCCESS",
        "visit Done SUCCESS"]
    assert ours[-1].endswith(" SUCCESS")


def test_initial_values_and_declarations_come_back(tmp_path: Path,
                                                   capsys: pytest.CaptureFixture[str]) -> None:
    tree, xml, back = (tmp_path / name for name in ("t.yaml", "t.xml", "back.yaml"))
    tree.write_text(INITIAL_TREE)
    plugins = ["--plugin-path", str(GENERIC)]
    assert main(["export", str(tree), "-o", str(xml), *plugins]) == 0
    text = xml.read_text()
    assert ('code="limit := 2; rate := 0.5; armed := true; label := &quot;it\'s ok&quot;; '
            "zones := 'a;b'; rounds := 0\"") in text
    assert '<Entry name="goal" type="int">Set by the caller.</Entry>' in text
    assert main(["import", str(xml), "-o", str(back), *plugins]) == 0, capsys.readouterr().err
    assert "InitialBlackboard" not in back.read_text()
    original, loaded = load_spec(tree, plugin_paths=[GENERIC]), load_spec(back)
    assert declarations(loaded) == declarations(original)
    assert loaded.declarations[""]["goal"].initial is original.declarations[""]["goal"].initial


def imported(xml: str, registry: Registry | None = None) -> dict[str, Any]:
    """The tree document ``xml`` imports to, without a problem."""
    result = import_btcpp(parse_xml(xml, "t.xml"), "t.xml", registry or default_registry())
    assert result.problems == [] and result.document is not None
    return result.document


def initial_blackboard(then_skip: str, code: str, condition: str) -> str:
    """A BT.CPP file whose tree starts with our ``InitialBlackboard`` wrapper of ``code``."""
    return f"""<root BTCPP_format="4"><BehaviorTree ID="T">
      <Sequence name="InitialBlackboard">
        <RunOnce name="InitialBlackboard" then_skip="{then_skip}">
          <Script name="InitialBlackboard" code="{code}"/>
        </RunOnce>
        <ScriptCondition code="{condition}"/>
      </Sequence></BehaviorTree></root>"""


def test_the_initial_values_alone_are_folded_back_typed_by_their_literals() -> None:
    """A file whose ``<Blackboard>`` was lost (an editor dropped it) keeps the values."""
    document = imported(initial_blackboard(
        "true", "a := 1; b := 2.5; c := 'x'; d := false",
        "a == 1 &amp;&amp; b &gt; 2 &amp;&amp; c == 'x' &amp;&amp; !d"))
    assert document["blackboard"] == {
        "a": {"type": "int", "initial": 1}, "b": {"type": "float", "initial": 2.5},
        "c": {"type": "str", "initial": "x"}, "d": {"type": "bool", "initial": False}}
    assert list(document["root"]) == ["ScriptCondition"]


@pytest.mark.parametrize("code", ["a := 1; b = 2", "a := b", "a := 1 + 1", "a += 1", ""])
def test_only_literal_assignments_are_initial_values(code: str) -> None:
    assert parse_initial(code) is None
    xml = f"""<Sequence name="InitialBlackboard">
        <RunOnce name="InitialBlackboard" then_skip="true">
          <Script name="InitialBlackboard" code="{code}"/></RunOnce><AlwaysSuccess/>
      </Sequence>"""
    assert unwrap_initial(parse_xml(xml, "t.xml")) is None


def test_a_script_that_merely_looks_alike_stays_a_node() -> None:
    document = imported(initial_blackboard("false", "a := 1", "a == 1"))
    assert "blackboard" not in document
    assert list(document["root"]) == ["Sequence"]


def test_curly_equals_on_import_is_the_entry_named_like_the_port() -> None:
    """``found="{=}"`` declares ``found`` (it used to declare an entry named ``=``)."""
    xml = """<root BTCPP_format="4"><BehaviorTree ID="T">
      <Sequence>
        <Scan zone="{zone}" found="{=}"/>
        <ScriptCondition code="found &gt; 0"/>
      </Sequence></BehaviorTree></root>"""
    section = imported(xml, extend(default_registry().copy(), [str(PORT_LEAVES)]))["blackboard"]
    assert list(section) == ["zone", "found"]
    assert section["found"]["type"] == "int"
    assert section["found"]["description"].startswith("Written by <Scan> port 'found'")
    assert section["zone"]["description"].startswith("Set by the caller")


def test_an_initial_text_with_both_quotes_is_a_located_export_error(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    tree = tmp_path / "t.yaml"
    tree.write_text("format: 1\nname: t\nblackboard:\n"
                    "  say: {type: str, initial: 'it''s \"x\"'}\n"
                    "root: {ScriptCondition: {code: \"say != ''\"}}\n")
    assert main(["export", str(tree), "-o", str(tmp_path / "t.xml")]) == 1
    err = capsys.readouterr().err
    assert f"{tree}:4:3: error:" in err and "both ' and" in err
    with pytest.raises(ValueError):
        export_btcpp(load_spec(tree), default_registry())
