"""A tree made of several files (``include:``, ``plugins:``, ``--plugin-path``), recorded by
``sar-tree run --record`` and replayed with its tree view after the files are gone."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from e2e.helpers import FAST, read_json, run_to_end

from recording.run_files import make_tree

pytestmark = [pytest.mark.ros, pytest.mark.slow]


def test_a_tree_of_several_files_replays_from_the_recording_alone(tmp_path: Path) -> None:
    tree, extra = make_tree(tmp_path / "sources")
    record = tmp_path / "mission.mcap"
    code, output = run_to_end([str(tree), "--plugin-path", str(extra), "--speed", FAST,
                               "--record", str(record)], tmp_path / "live")
    assert code == 0, output
    live = read_json(tmp_path / "live" / "mission.json")
    shutil.rmtree(tmp_path / "sources")  # the tree, its include and both plugins

    result = subprocess.run([sys.executable, "-m", "sar_framework", "replay", str(record),
                             "--report-dir", str(tmp_path / "replayed")],
                            capture_output=True, text=True, timeout=60, check=False)
    assert result.returncode == 0, result.stderr
    assert "warning" not in result.stderr, result.stderr
    replayed = read_json(tmp_path / "replayed" / "mission.json")
    assert replayed["outcome"] == live["outcome"] == "SUCCESS"
    assert replayed["node_statuses"] == live["node_statuses"]
    svg = (tmp_path / "replayed" / "tree.svg").read_text()
    # the main file's nodes, the --plugin-path leaf, the included subtree and its plugin's
    for name in ("IncludedAndPlugins", "FirstPause", "ReportSurvivor", "TakeId"):
        assert name in svg, name
    assert (tmp_path / "replayed" / "recorded_files" / "extra" / "pause.py").is_file()
