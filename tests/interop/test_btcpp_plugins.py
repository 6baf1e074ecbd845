"""A tree's ``plugins:`` survive ``sar-tree export`` and ``sar-tree import``: BT.CPP loads
the XML that carries them, and the tree imported back validates with no ``--plugin-path``."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from interop.test_btcpp_roundtrip import loaded_by_btcpp
from sar_framework.cli import main
from sar_framework.engine.api import validate

pytestmark = pytest.mark.timeout(600)  # outer safety bound (a cold BT.CPP checker)
REPO = Path(__file__).resolve().parents[2]
TUTORIAL = REPO / "trees" / "tutorials"


@pytest.fixture
def tree(tmp_path: Path) -> Path:
    """The plugin tutorial's tree and its plugin file, in a folder of their own."""
    folder = tmp_path / "mine"
    shutil.copytree(TUTORIAL / "plugins", folder / "plugins")
    shutil.copy(TUTORIAL / "02_writing_a_plugin.yaml", folder / "tree.yaml")
    return folder / "tree.yaml"


def test_exported_plugins_bring_the_tree_back_with_no_flag(
        tree: Path, tmp_path: Path, btcpp_checker: Path,
        capsys: pytest.CaptureFixture[str]) -> None:
    xml = tmp_path / "out" / "tree.xml"
    xml.parent.mkdir()
    assert main(["export", str(tree), "-o", str(xml)]) == 0, capsys.readouterr().err
    assert '<Plugin path="../mine/plugins/tutorial_leaves.py" />' in xml.read_text()
    loaded_by_btcpp(btcpp_checker, xml)  # BT.CPP's parser passes over <Plugins>

    back = tmp_path / "elsewhere" / "back.yaml"
    back.parent.mkdir()
    assert main(["import", str(xml), "-o", str(back)]) == 0, capsys.readouterr().err
    assert "plugins: [../mine/plugins/tutorial_leaves.py]\n" in back.read_text()
    assert validate(back).ok
    assert main(["export", str(back), "-o", str(xml)]) == 0  # and round again, the same
    assert '<Plugin path="../mine/plugins/tutorial_leaves.py" />' in xml.read_text()


def test_a_plugin_path_flag_given_to_export_is_kept_too(
        tree: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    text = tree.read_text().replace("plugins: [plugins/tutorial_leaves.py]\n", "")
    tree.write_text(text)
    flag = ["--plugin-path", str(tree.parent / "plugins")]
    assert main(["export", str(tree), "-o", str(tmp_path / "t.xml"), *flag]) == 0
    assert main(["import", str(tmp_path / "t.xml"), "-o", str(tmp_path / "t.yaml")]) == 0, (
        capsys.readouterr().err)
    assert validate(tmp_path / "t.yaml").ok


def test_a_module_entry_is_written_as_a_module(tmp_path: Path) -> None:
    tree = tmp_path / "tree.yaml"
    tree.write_text("format: 1\nname: t\nplugins: [sar_plugins.nav2]\n"
                    "root:\n  AlwaysSuccess: {}\n")
    assert main(["export", str(tree), "-o", str(tmp_path / "t.xml")]) == 0
    assert '<Plugin module="sar_plugins.nav2" />' in (tmp_path / "t.xml").read_text()
    assert main(["import", str(tmp_path / "t.xml"), "-o", str(tmp_path / "b.yaml")]) == 0
    assert "plugins: [sar_plugins.nav2]\n" in (tmp_path / "b.yaml").read_text()


def test_a_malformed_plugins_entry_is_located(tmp_path: Path,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    xml = tmp_path / "t.xml"
    xml.write_text('<root BTCPP_format="4">\n  <Plugins>\n    <Plugin file="x.py"/>\n'
                   '  </Plugins>\n  <BehaviorTree ID="t"><AlwaysSuccess/></BehaviorTree>\n'
                   '</root>\n')
    assert main(["import", str(xml)]) == 1
    err = capsys.readouterr().err
    assert f"{xml}:3:5: error: <Plugin> in <Plugins>: expected" in err, err
    assert "Traceback" not in err
