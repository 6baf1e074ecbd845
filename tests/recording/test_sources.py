"""The files a run was made of (tree, includes, local plugins), as a recording keeps them."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from recording.run_files import make_tree
from sar_framework.engine.api import validate
from sar_framework.recording.sources import (
    PLUGIN_PATHS_KEY,
    TREE_KEY,
    SourcesError,
    collect,
    extract,
)


def test_a_run_keeps_its_tree_includes_and_plugin_sources(tmp_path: Path) -> None:
    tree, extra = make_tree(tmp_path)
    assert validate(tree, plugin_paths=[extra]).ok
    kept = collect(str(tree), [str(extra), "sar_plugins"])
    assert sorted(kept.attachments) == [
        "files/extra/pause.py", "files/mission/common/06_report_library.yaml",
        "files/mission/plugins/tutorial_leaves.py", "files/mission/tree.yaml"]
    assert kept.attachments["files/mission/tree.yaml"] == tree
    assert kept.metadata[TREE_KEY] == "files/mission/tree.yaml"
    # an installed module is named, not copied
    assert json.loads(kept.metadata[PLUGIN_PATHS_KEY]) == ["files/extra", "sar_plugins"]


def test_relative_plugin_paths_start_at_the_runs_folder(tmp_path: Path) -> None:
    make_tree(tmp_path)
    kept = collect("mission/tree.yaml", ["extra/pause.py"], cwd=tmp_path)
    assert "files/extra/pause.py" in kept.attachments
    assert json.loads(kept.metadata[PLUGIN_PATHS_KEY]) == ["files/extra/pause.py"]


def test_the_files_written_out_validate_without_the_originals(tmp_path: Path) -> None:
    tree, extra = make_tree(tmp_path / "original")
    kept = collect(str(tree), [str(extra)])
    attachments = {name: path.read_bytes() for name, path in kept.attachments.items()}
    shutil.rmtree(tmp_path / "original")
    files = extract(attachments, kept.metadata, tmp_path / "out")
    assert files.tree == tmp_path / "out" / "mission" / "tree.yaml"
    assert files.plugin_paths == [str(tmp_path / "out" / "extra")]
    result = validate(files.tree, plugin_paths=files.plugin_paths)
    assert result.ok, result.diagnostics
    assert [n.name for n in result.spec.nodes()][:2] == ["IncludedAndPlugins", "FirstPause"]


def test_a_missing_tree_keeps_nothing(tmp_path: Path) -> None:
    kept = collect(str(tmp_path / "gone.yaml"))
    assert kept.attachments == {} and kept.metadata == {}


@pytest.mark.parametrize("name", ["files/../escape.py", "files//etc/passwd"])
def test_an_attachment_outside_the_files_is_refused(tmp_path: Path, name: str) -> None:
    with pytest.raises(SourcesError, match="outside the recording's files"):
        extract({name: b"x"}, {}, tmp_path)


def test_malformed_plugin_paths_are_named(tmp_path: Path) -> None:
    with pytest.raises(SourcesError, match="'plugin_paths' is not JSON"):
        extract({}, {PLUGIN_PATHS_KEY: "[oops"}, tmp_path)
