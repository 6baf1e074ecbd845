"""Replay keeps the final blackboard entry values: status.json, then mission.json."""

from __future__ import annotations

import json
from pathlib import Path

from sar_framework.recording.readback import Recording, status_document, write_report_inputs
from sar_framework.report import MissionInputs, summarise
from sar_framework.runner.tree_status import decode_status

REPO = Path(__file__).resolve().parents[2]


def status(tick: int, entries: list[list[str]] | None, full: bool = False) -> dict:
    document = {"format": 1, "tree": "t", "tick": tick, "sim_s": tick * 0.5, "status": "RUNNING",
                "complete": False, "nodes": [["0", "Walk", "Walk", "RUNNING", "", True]]}
    if entries is not None:
        document.update(entries=entries, entries_full=full)
    decoded = decode_status(json.dumps(document))
    decoded["wall_s"] = tick * 0.1
    return decoded


def test_the_final_entry_values_reach_status_json_and_mission_json(tmp_path) -> None:
    recording = Recording(path=tmp_path / "run.mcap", statuses=[
        status(1, [["count", "/count", "-", "unset", "Walk"],
                   ["label", "/label", "'north'", "str", ""]], full=True),
        status(2, [["count", "/count", "1", "int", "Walk"]]),
        status(3, []),
        status(4, [["count", "/count", "2", "int", "Walk"]]),
    ])
    document = status_document(recording)
    assert document["entries"] == {
        "count": {"name": "count", "key": "/count", "value": "2", "type": "int",
                  "writer": "Walk"},
        "label": {"name": "label", "key": "/label", "value": "'north'", "type": "str",
                  "writer": ""}}
    write_report_inputs(recording, tmp_path)
    params = REPO / "config" / "mission_params.yaml"
    summary = summarise(MissionInputs(
        report_dir=tmp_path, tree="t.yaml", params_file=str(params), spec=None,
        outcome="INTERRUPTED", wall_duration_s=1.0))
    assert summary["entries"]["count"]["value"] == "2"


def test_a_recording_without_entries_adds_no_key(tmp_path) -> None:
    recording = Recording(path=tmp_path / "run.mcap", statuses=[status(1, None)])
    assert "entries" not in status_document(recording)
