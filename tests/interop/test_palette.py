"""``sar-tree palette``: our Groot2 palette, and proof that it never drifts from the kinds.

The palette is read back with the importer's model reader: every registered leaf is there,
an Action or a Condition, with its params and ports (direction, type, default,
description) and its description; so is every control, decorator and built-in leaf kind
under its BT.CPP ID, and every py_trees kind BT.CPP has no node for as its ``Sar...``
node. Nav2's controls and decorators are Nav2's own palette's, node for node and port
for port. The committed ``sar_framework/schema/tree_nodes.xml`` is what the built-in
registry gives now (no app's leaf), ``plugins/sar/schema/tree_nodes.xml`` what it gives with
the search-and-rescue app's leaves, and third-party plugins join the palette.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from sar_framework.cli import main
from sar_framework.engine.nodes.control_kinds import CONTROL_KINDS
from sar_framework.engine.nodes.kind_model import AttrType
from sar_framework.engine.nodes.node_kinds import PY_TREES_KINDS, SCRIPT_KINDS
from sar_framework.engine.param import REQUIRED
from sar_framework.engine.ports import NO_DEFAULT, PYTHON_TYPES, convert
from sar_framework.engine.registry import Registry, discover, extend
from sar_framework.interop.btcpp_file import read_palette
from sar_framework.interop.btcpp_models import literal_default
from sar_framework.interop.btcpp_palette import palette_text
from sar_framework.interop.mapping import always_builtin, custom_id
from sar_framework.testing.nav2_navigators import nav2_share

REPO = Path(__file__).resolve().parents[2]
COMMITTED = REPO / "sar_framework" / "schema" / "tree_nodes.xml"
SAR_COMMITTED = REPO / "plugins" / "sar" / "schema" / "tree_nodes.xml"
SAR_LEAVES = "sar_plugins.sar.leaves"
PORT_PLUGINS = REPO / "tests" / "engine" / "plugins_for_tests" / "ports" / "port_plugins.py"


def read_back(text: str, tmp_path: Path) -> dict:
    path = tmp_path / "palette.xml"
    path.write_text(text)
    models, problems = read_palette(str(path))
    assert not problems
    return models


#: The IDs of the engine's node kinds in the palette: BT.CPP's, then the custom ``Sar...``.
KIND_IDS = {*(k.key for k in (*CONTROL_KINDS, *SCRIPT_KINDS)),
            *(custom_id(k) for k in PY_TREES_KINDS.values() if not always_builtin(k))}


def assert_same(registry: Registry, models: dict) -> None:
    assert sorted(set(models) - KIND_IDS) == sorted(
        [*registry.names(), *(k.name for k in registry.kind_plugins())])
    for plugin in registry:
        model = models[plugin.name]
        assert model.category == ("Condition" if plugin.condition else "Action"), plugin.name
        names = ["id", *(p.name for p in plugin.params), *(p.name for p in plugin.ports)]
        assert [p.name for p in model.ports] == names, plugin.name
        for param in plugin.params:
            port = model.port(param.name)
            assert port.direction == "input"
            want = None if param.default is REQUIRED else param.default
            assert literal_default(port) == want, (plugin.name, param.name)
            assert port.type == ("str" if param.ref else PYTHON_TYPES[param.type])
        for declared in plugin.ports:
            port = model.port(declared.name)
            where = (plugin.name, declared.name)
            assert port.direction == declared.direction.value, where
            assert port.type == declared.type, where
            want = None if declared.default is NO_DEFAULT else declared.default
            got = literal_default(port)
            if declared.type == "list" and isinstance(got, str):
                got = convert("list", got)  # BT.CPP's 'a;b;c'
            assert got == want, where
            assert port.description == " ".join(declared.description.split()), where


def test_every_kind_is_in_the_palette_with_its_ports(tmp_path: Path) -> None:
    registry = discover(entry_points=False)
    models = read_back(palette_text(registry), tmp_path)
    assert set(models) >= KIND_IDS
    categories = {AttrType.NODES: "Control", AttrType.NODE: "Decorator"}
    for kind in (*CONTROL_KINDS, *SCRIPT_KINDS, *(k.kind for k in registry.kind_plugins())):
        model = models[kind.key]
        shape = next((categories[a.type] for a in kind.attrs if a.type in categories), None)
        assert model.category == (shape or ("Condition" if kind.key == "ScriptCondition"
                                            else "Action")), kind.key
        own = kind.settings()
        assert [p.name for p in model.ports] == [a.name for a in own], kind.key
        assert not {"name", "child", "children", "_skipIf"} & {a.name for a in own}
        for attr in (a for a in own if a.port is not None):
            port = model.port(attr.name)
            assert (port.direction, port.type) == (attr.port.direction.value,
                                                   attr.port.type), (kind.key, attr.name)
    # BT.CPP ticks a `sequence` as its Sequence; a `parallel` only as our custom node
    assert "SarSequence" not in models and "SarInverter" not in models
    assert [p.name for p in models["SarParallel"].ports] == ["policy", "synchronise",
                                                              "selected"]
    assert models["Repeat"].port("num_cycles").type == "int"
    assert literal_default(models["RecoveryNode"].port("number_of_retries")) == 1


def test_nav2s_controls_and_decorators_are_nav2s_palettes(tmp_path: Path) -> None:
    """Node for node and port for port: name, direction, type and default."""
    theirs, problems = read_palette(str(nav2_share("nav2_behavior_tree", "nav2_tree_nodes.xml")))
    assert not problems
    theirs = {key: m for key, m in theirs.items() if m.category in ("Control", "Decorator")}
    registry = discover(entry_points=False)
    ours = read_back(palette_text(registry), tmp_path)
    assert sorted(theirs) == sorted(k.name for k in registry.kind_plugins()
                                    if k.cls.__module__.startswith("sar_plugins.nav2."))
    for key, model in theirs.items():
        mine = ours[key]
        assert mine.category == model.category, key
        assert [(p.name, p.direction, p.type, literal_default(p)) for p in mine.ports] == [
            (p.name, p.direction, p.type, literal_default(p)) for p in model.ports], key


def description_of(text: str, leaf: str) -> str:
    block = text.split(f'ID="{leaf}"', maxsplit=1)[1]
    return block.split("<description>", maxsplit=1)[1].split("</description>", maxsplit=1)[0]


def test_the_palette_is_the_registry(tmp_path: Path) -> None:
    registry = discover(entry_points=False)
    text = palette_text(registry)
    assert_same(registry, read_back(text, tmp_path))
    assert description_of(text, "Spin") == "Nav2's Spin: turn in place by ``spin_dist`` radians."
    assert '<Condition ID="GoalReached">' in text and '<Action ID="FollowPath">' in text
    assert "Survivor" not in text  # the app's leaves are the app's palette's
    app = discover([SAR_LEAVES], entry_points=False)
    app_text = palette_text(app)
    assert_same(app, read_back(app_text, tmp_path))
    assert '<Condition ID="IsSurvivorDetected">' in app_text


def test_the_committed_palette_is_up_to_date() -> None:
    assert COMMITTED.read_text(encoding="utf-8") == palette_text(discover(entry_points=False)), (
        "sar_framework/schema/tree_nodes.xml is stale: run "
        "`sar-tree palette --core -o sar_framework/schema/tree_nodes.xml`")


def test_the_committed_app_palette_is_up_to_date(capsys: pytest.CaptureFixture[str]) -> None:
    expected = palette_text(discover([SAR_LEAVES], entry_points=False))
    assert SAR_COMMITTED.read_text(encoding="utf-8") == expected, (
        "plugins/sar/schema/tree_nodes.xml is stale: run `sar-tree palette --core "
        f"--plugin-path {SAR_LEAVES} -o plugins/sar/schema/tree_nodes.xml`")
    assert main(["palette", "--core", "--plugin-path", SAR_LEAVES]) == 0
    assert capsys.readouterr().out == expected


def test_a_changed_leaf_changes_the_palette(tmp_path: Path) -> None:
    """The comparison can fail: a port's default the palette does not say is caught."""
    import dataclasses

    registry = discover(entry_points=False)
    models = read_back(palette_text(registry), tmp_path)
    spin = registry.get("Spin")
    moved = tuple(dataclasses.replace(p, default=3.0) if p.name == "spin_dist" else p
                  for p in spin.ports)
    changed = [dataclasses.replace(p, ports=moved) if p.name == "Spin" else p for p in registry]

    class Changed:
        names = registry.names
        kind_plugins = registry.kind_plugins

        def __iter__(self):
            return iter(changed)

    with pytest.raises(AssertionError, match="spin_dist"):
        assert_same(Changed(), models)  # type: ignore[arg-type]


def test_third_party_plugins_join_the_palette(tmp_path: Path,
                                              capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "palette.xml"
    assert main(["palette", "--core", "--plugin-path", str(PORT_PLUGINS), "-o", str(out)]) == 0
    registry = extend(discover(entry_points=False), [PORT_PLUGINS])
    assert_same(registry, read_back(out.read_text(), tmp_path))
    assert '<Action ID="Plan">' in out.read_text()
    # without --core, every installed plugin joins too (the search-and-rescue app's leaves)
    assert main(["palette", "--plugin-path", str(PORT_PLUGINS), "-o", str(out)]) == 0
    assert_same(extend(discover(), [PORT_PLUGINS]), read_back(out.read_text(), tmp_path))
    assert main(["palette", "--plugin-path", str(tmp_path / "nope.py")]) == 1
    assert "plugin path" in capsys.readouterr().err
