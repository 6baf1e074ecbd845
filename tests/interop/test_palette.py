"""``sar-tree palette``: our Groot2 palette, and proof that it never drifts from the registry.

The palette is read back with the importer's model reader: every registered leaf is there,
an Action or a Condition, with its params and ports (direction, type, default,
description) and its description; the committed ``sar_framework/schema/tree_nodes.xml``
is what the built-in registry gives now, and third-party plugins join the palette.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from sar_framework.cli import main
from sar_framework.engine.param import REQUIRED
from sar_framework.engine.ports import NO_DEFAULT, PYTHON_TYPES, convert
from sar_framework.engine.registry import Registry, discover, extend
from sar_framework.interop.btcpp_file import read_palette
from sar_framework.interop.btcpp_models import literal_default
from sar_framework.interop.btcpp_palette import palette_text

REPO = Path(__file__).resolve().parents[2]
COMMITTED = REPO / "sar_framework" / "schema" / "tree_nodes.xml"
PORT_PLUGINS = REPO / "tests" / "engine" / "plugins_for_tests" / "ports" / "port_plugins.py"


def read_back(text: str, tmp_path: Path) -> dict:
    path = tmp_path / "palette.xml"
    path.write_text(text)
    models, problems = read_palette(str(path))
    assert not problems
    return models


def assert_same(registry: Registry, models: dict) -> None:
    assert sorted(models) == registry.names()
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


def description_of(text: str, leaf: str) -> str:
    block = text.split(f'ID="{leaf}"', maxsplit=1)[1]
    return block.split("<description>", maxsplit=1)[1].split("</description>", maxsplit=1)[0]


def test_the_palette_is_the_registry(tmp_path: Path) -> None:
    registry = discover(entry_points=False)
    text = palette_text(registry)
    assert_same(registry, read_back(text, tmp_path))
    assert description_of(text, "Spin") == "Nav2's Spin: turn in place by ``spin_dist`` radians."
    assert '<Condition ID="GoalReached">' in text and '<Action ID="FollowPath">' in text
    assert '<Condition ID="IsSurvivorDetected">' in text


def test_the_committed_palette_is_up_to_date() -> None:
    assert COMMITTED.read_text(encoding="utf-8") == palette_text(discover(entry_points=False)), (
        "sar_framework/schema/tree_nodes.xml is stale: run "
        "`sar-tree palette -o sar_framework/schema/tree_nodes.xml`")


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

        def __iter__(self):
            return iter(changed)

    with pytest.raises(AssertionError, match="spin_dist"):
        assert_same(Changed(), models)  # type: ignore[arg-type]


def test_third_party_plugins_join_the_palette(tmp_path: Path,
                                              capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "palette.xml"
    assert main(["palette", "--plugin-path", str(PORT_PLUGINS), "-o", str(out)]) == 0
    registry = extend(discover(entry_points=False), [PORT_PLUGINS])
    assert_same(registry, read_back(out.read_text(), tmp_path))
    assert '<Action ID="Plan">' in out.read_text()
    assert main(["palette", "--plugin-path", str(tmp_path / "nope.py")]) == 1
    assert "plugin path" in capsys.readouterr().err
