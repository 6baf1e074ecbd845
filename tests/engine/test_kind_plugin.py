"""A plugin's control node and decorator, taken exactly as the engine's own kinds.

The test plugins (``plugins_for_tests/kinds``: ``Majority``, a control, and ``Twice``, a
decorator) touch no engine file; each validates, renders, exports to BT.CPP's XML, imports
back, is in the palette and ticks.
"""

from __future__ import annotations

import textwrap
from pathlib import Path

import py_trees
import pytest
import yaml
from py_trees.common import Status

from sar_framework.engine.api import load_spec, load_tree
from sar_framework.engine.checking.validate import validate_file
from sar_framework.engine.kind_plugin import decorator_kind, node_kind
from sar_framework.engine.registry import Registry, default_registry, extend
from sar_framework.engine.rendering.render import render_dot
from sar_framework.engine.rendering.text_tree import render_text
from sar_framework.interop.btcpp_export import export_btcpp
from sar_framework.interop.btcpp_import import import_btcpp
from sar_framework.interop.btcpp_palette import palette_text
from sar_framework.interop.xml_source import parse_xml
from sar_framework.plugin_catalogue import kind_lines

HERE = Path(__file__).resolve().parent
KIND_PLUGINS = HERE / "plugins_for_tests" / "kinds"
GENERIC = HERE / "plugins_for_tests" / "generic"

TREE = """\
format: 1
plugins: [{kinds}, {generic}]
root:
  Twice:
    times: 2
    child:
      Majority:
        name: vote
        children:
          - Fixed: {{status: success}}
          - Fixed: {{status: failure}}
          - Fixed: {{status: success}}
"""


def _registry() -> Registry:
    return extend(default_registry().copy(), [KIND_PLUGINS, GENERIC])


def _tree(tmp_path: Path, text: str = TREE) -> Path:
    path = tmp_path / "tree.yaml"
    path.write_text(text.format(kinds=KIND_PLUGINS, generic=GENERIC), encoding="utf-8")
    return path


def test_the_registry_finds_the_plugin_kinds() -> None:
    registry = _registry()
    found = [k.name for k in registry.kind_plugins() if not k.source.startswith("sar_plugins")]
    assert found == ["Majority", "Twice"]
    assert "Majority" not in registry  # not a leaf
    assert not registry.diagnostics


def test_they_validate_and_tick(tmp_path: Path) -> None:
    loaded = load_tree(_tree(tmp_path))
    root = loaded.root
    assert type(root).__name__ == "Twice"
    assert [type(c).__name__ for c in root.children] == ["Majority"]
    statuses = []
    for _ in range(2):
        root.tick_once()
        statuses.append(root.status)
    assert statuses == [Status.RUNNING, Status.SUCCESS]


def test_a_bad_value_is_reported_at_its_line(tmp_path: Path) -> None:
    path = _tree(tmp_path, TREE.replace("times: 2", "times: 0"))
    found = [(d.location.line, d.message) for d in validate_file(path).diagnostics]
    assert len(found) == 1 and found[0][0] == 5 and "times" in found[0][1], found
    path = _tree(tmp_path, TREE.replace("times: 2", "tims: 2"))
    messages = [d.message for d in validate_file(path).diagnostics]
    assert len(messages) == 1 and "did you mean 'times'" in messages[0], messages


def test_they_render(tmp_path: Path) -> None:
    spec = load_spec(_tree(tmp_path))
    text = render_text(spec)
    assert "Twice" in text and "vote" in text
    dot = render_dot(spec)
    assert "vote" in dot and "Twice" in dot


def test_they_export_and_import_back(tmp_path: Path) -> None:
    registry = _registry()
    spec = load_spec(_tree(tmp_path), registry=registry)
    xml = export_btcpp(spec, registry)
    assert '<Twice name="Twice" times="2">' in xml
    assert '<Majority name="vote" quorum="0">' in xml
    assert '<Decorator ID="Twice">' in xml and '<Control ID="Majority">' in xml
    result = import_btcpp(parse_xml(xml, "t.xml"), "t.xml", registry)
    assert not result.problems, result.problems
    assert result.document is not None
    document = {**result.document, "plugins": [str(KIND_PLUGINS), str(GENERIC)]}
    back = tmp_path / "back.yaml"
    back.write_text(yaml.safe_dump(document, sort_keys=False), encoding="utf-8")
    again = load_spec(back, registry=registry)
    assert export_btcpp(again, registry) == xml


def test_an_imported_spelling_names_the_plugin_kind() -> None:
    xml = textwrap.dedent("""\
        <root BTCPP_format="4" main_tree_to_execute="Main">
          <BehaviorTree ID="Main">
            <RepeatTwice times="3"><AlwaysSuccess/></RepeatTwice>
          </BehaviorTree>
        </root>
        """)
    result = import_btcpp(parse_xml(xml, "t.xml"), "t.xml", _registry())
    assert not result.problems, result.problems
    assert result.document is not None
    assert result.document["root"]["Twice"]["times"] == 3


def test_they_are_in_the_palette_and_the_kinds_listing() -> None:
    registry = _registry()
    palette = palette_text(registry)
    assert '<Control ID="Majority">' in palette and '<Decorator ID="Twice">' in palette
    lines = kind_lines(registry)
    assert "Majority  [composite]" in lines and "Twice  [decorator]" in lines


def test_a_plugin_kind_may_not_take_an_engine_kind_s_name() -> None:
    @node_kind(decorator_kind("Inverter", "Not the engine's."))
    class Imposter(py_trees.decorators.Decorator):
        pass

    registry = Registry()
    registry.add(Imposter, "here")
    assert [d.message for d in registry.diagnostics] == [
        "plugin name 'Inverter' is reserved (from here)"]
    assert registry.kind("Inverter") is None


def test_a_leaf_kind_is_refused() -> None:
    from sar_framework.engine.nodes.kind_model import NodeKind
    from sar_framework.engine.spec import Category

    with pytest.raises(TypeError, match="declared with @leaf"):
        node_kind(NodeKind("Odd", Category.LEAF, "Odd", "A leaf.", ()))(type("Odd", (), {}))
