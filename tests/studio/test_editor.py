"""The studio's tree editor without a browser: checks read as ``sar-tree validate``'s,
completion comes from the JSON Schema, saving needs the token and stays in the roots."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from sar_framework.cli import main
from sar_framework.studio.editor import CHECK_PREFIX, TreeEditor
from sar_framework.studio.safety import RefusedError
from sar_framework.studio.server import TOKEN_HEADER, make_app
from sar_framework.studio.session import EDIT, Session

REPO = Path(__file__).resolve().parents[2]
TUTORIALS = REPO / "trees" / "tutorials"
pytestmark = pytest.mark.skipif(shutil.which("dot") is None, reason="Graphviz is not installed")


@pytest.fixture
def tree(tmp_path: Path) -> Path:
    shutil.copytree(TUTORIALS / "common", tmp_path / "common")
    shutil.copytree(TUTORIALS / "plugins", tmp_path / "plugins")
    path = tmp_path / "tree.yaml"
    shutil.copy(TUTORIALS / "06_subtrees_and_include.yaml", path)
    return path


def test_a_valid_text_gives_its_diagram_and_leaves_no_file(tree: Path) -> None:
    editor = TreeEditor(tree, [tree.parent])
    checked = editor.check(editor.text())
    assert checked["ok"], checked["diagnostics"]
    assert checked["diagnostics"] == []
    assert "<svg" in checked["tree"]["svg"]
    assert not list(tree.parent.glob(f"{CHECK_PREFIX}*"))  # the checked copy is gone


def test_a_broken_text_reads_as_sar_tree_validate_prints_it(tree: Path, capsys) -> None:
    editor = TreeEditor(tree, [tree.parent])
    broken = editor.text().replace("include:", "includes:", 1)
    checked = editor.check(broken)
    assert not checked["ok"] and checked["tree"] is None
    tree.write_text(broken)
    assert main(["validate", str(tree)]) == 1
    printed = [line for line in capsys.readouterr().err.splitlines() if ": error: " in line]
    assert [d["text"] for d in checked["diagnostics"] if d["severity"] == "error"] == printed
    assert printed and printed[0].startswith(f"{tree}:")


def test_completion_lists_the_schema_kinds_and_their_params(tree: Path) -> None:
    completions = TreeEditor(tree, [tree.parent]).completions()
    assert {"format", "name", "root", "include", "subtrees"} <= set(completions["top"])
    assert "num_failures" in completions["kinds"]["retry"]["params"]
    assert "AdvanceZone" in completions["kinds"]
    assert "Sequence" in completions["kinds"]  # BT.CPP's names too


def test_saving_writes_the_file_and_stays_in_the_roots(tree: Path, tmp_path: Path) -> None:
    editor = TreeEditor(tree, [tree.parent])
    saved = editor.save(editor.text() + "# edited\n")
    assert saved["ok"] and tree.read_text().endswith("# edited\n")
    with pytest.raises(RefusedError, match="outside the directories open to the studio"):
        TreeEditor(tmp_path.parent / "elsewhere.yaml", [tree.parent])
    with pytest.raises(RefusedError, match="more than"):
        editor.save("x" * 70_000)


def test_save_over_http_needs_the_token(tree: Path) -> None:
    testclient = pytest.importorskip("starlette.testclient", reason="httpx is not installed")
    editor = TreeEditor(tree, [tree.parent])
    session = Session(EDIT, None, {"grid": None, "places": [], "base": None}, str(tree))
    before = tree.read_text()
    with testclient.TestClient(make_app(session, "k" * 48, editor)) as client:
        assert client.post("/api/save", json={"text": "x"}).status_code == 403
        assert tree.read_text() == before
        assert client.post("/api/save", headers={TOKEN_HEADER: "k" * 48},
                           content=b"not json").status_code == 400
        answer = client.post("/api/save", headers={TOKEN_HEADER: "k" * 48},
                             json={"text": before + "# saved\n"})
        assert answer.status_code == 200 and answer.json()["ok"]
        assert tree.read_text() == before + "# saved\n"
        with client.websocket_connect("/ws") as ws:
            ws.receive_json(), ws.receive_json()
            ws.send_json({"op": "check", "text": "format: 1\nname: x\nroot: {Nope: {}}\n"})
            checked = ws.receive_json()
            assert checked["type"] == "checked" and not checked["ok"]
            assert "unknown plugin 'Nope'" in checked["diagnostics"][0]["text"]
