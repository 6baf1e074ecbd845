"""Log text is for humans: reword every log line and the verdict, report and recording hold.

Every ROS process of the run (the runner with its plugins, the servers, the simulator) gets
a ``sitecustomize`` that rewrites each log message before rcutils prints it (reversed, with
a marker). Nothing that decides anything reads log text, so the exit code, the progress
lines, ``mission.json`` and the events in the recording are those of an ordinary run.

The ordinary run (a module fixture) also serves the refusing report server's own test and
the reference tree's check that ``status.json`` and ``tree.svg`` agree with the events
(``test_views_agree_with_events``): two missions fewer (the suite's time budget).
"""

from __future__ import annotations

import os
import re
from pathlib import Path
from typing import Any

import pytest
from sar_plugins.sar.events import SarKind

from sar_framework.events.event import EventKind

from .helpers import DEFAULT_TREE, FAST, no_traceback, read_json, read_jsonl, run_to_end
from .test_views_agree_with_events import (
    check_completes_without_a_tip_error,
    check_views_agree_with_the_events,
)

pytestmark = [pytest.mark.slow, pytest.mark.ros]

MARK = "~reworded~ "
SITECUSTOMIZE = f'''\
"""Test hook: reword every rclpy log message (see tests/e2e/test_log_wording.py)."""
import rclpy.impl.rcutils_logger as _logger


class _Reworded:
    def __init__(self, inner):
        self._inner = inner

    def __getattr__(self, name):
        return getattr(self._inner, name)

    def rclpy_logging_rcutils_log(self, severity, name, message, *where):
        return self._inner.rclpy_logging_rcutils_log(
            severity, name, {MARK!r} + str(message)[::-1], *where)


_logger._rclpy = _Reworded(_logger._rclpy)
'''
PROGRESS = re.compile(r"^\[\s*[0-9.]+s\] runner \| (?!WARN: |ERROR: )(.*)$", re.MULTILINE)


@pytest.fixture(scope="module")
def plain(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    """An ordinary run of the reference tree with a report server that refuses every report."""
    return {"tree": DEFAULT_TREE, **_run(tmp_path_factory.mktemp("plain"), "plain", {})}


def test_the_reference_tree_completes_without_a_tip_error(plain: dict[str, Any]) -> None:
    check_completes_without_a_tip_error(plain)


def test_the_reference_trees_status_json_and_tree_svg_agree_with_the_events(
        plain: dict[str, Any]) -> None:
    check_views_agree_with_the_events(plain)


def test_refusing_report_server_the_mission_goes_on_and_says_why(plain: dict[str, Any]) -> None:
    """The reference tree falls back to LogNoDetection when NotifyBase fails."""
    code, out, report = plain["code"], plain["out"], plain["report"]
    assert code == 0, out
    assert "Report refused: 'survivor_1'" in out
    assert "NotifyBase [0.0.3.0.2] failed on the way: report of survivor_1" in out
    mission = read_json(report / "mission.json")
    assert [(s["id"], s["acknowledged"]) for s in mission["survivors"]] == [
        ("survivor_1", False), ("survivor_2", False)]
    assert not (report / "reports.jsonl").exists() or \
        read_jsonl(report / "reports.jsonl") == []
    assert no_traceback(out)


def _run(tmp_path: Path, name: str, env: dict[str, str]) -> dict[str, Any]:
    report = tmp_path / name
    record = tmp_path / f"{name}.mcap"
    saved = dict(os.environ)
    os.environ.update(env)
    try:
        code, out = run_to_end([str(DEFAULT_TREE), "--speed", FAST, "--report-param",
                                "refuse_all:=true", "--record", str(record)], report)
    finally:
        os.environ.clear()
        os.environ.update(saved)
    return {"code": code, "out": out, "report": report, "record": record}


def _verdict(run: dict[str, Any]) -> tuple[int, list[str], str]:
    summary = next(line for line in run["out"].splitlines()
                   if line.startswith("sar-tree run: Mission "))
    return run["code"], PROGRESS.findall(run["out"]), re.sub(r"[0-9.]+ s|\d+ ticks", "#", summary)


def _mission(summary: dict[str, Any]) -> dict[str, Any]:
    return {
        "outcome": (summary["outcome"], summary["reason"], summary["root_status"]),
        "zones": ([z["id"] for z in summary["zones_visited"]], summary["zones_skipped"],
                  summary["base_reached"] is not None),
        "survivors": [(s["id"], s["x"], s["y"], s["acknowledged"], s.get("refused"))
                      for s in summary["survivors"]],
        "failures": [(f["what"], f["uid"], f["name"], f["message"])
                     for f in summary["failures"]],
        "goals": summary["navigation_goals"],
    }


def _recorded(record: Path) -> tuple[list[tuple[Any, ...]], dict[str, Any]]:
    from sar_framework.recording.readback import read_recording, write_report_inputs
    from sar_framework.report import MissionInputs, summarise

    recording = read_recording(record)
    told = [(e.kind, e.node_uid, e.node_name, e.status, e.value("zone_id"), e.value("survivor_id"),
             e.position, e.message) for e in recording.events if e.kind != EventKind.STATUS]
    folder = record.with_suffix("")
    files = write_report_inputs(recording, folder)
    replayed = summarise(MissionInputs(folder, str(DEFAULT_TREE), str(files["params"]), None,
                                       "SUCCESS"))
    return told, replayed


def test_rewording_every_log_line_changes_no_verdict_report_or_recording(
        plain: dict[str, Any], tmp_path: Path) -> None:
    hook = tmp_path / "hook"
    hook.mkdir()
    (hook / "sitecustomize.py").write_text(SITECUSTOMIZE)
    reworded = _run(tmp_path, "reworded", {
        "PYTHONPATH": os.pathsep.join([str(hook), os.environ.get("PYTHONPATH", "")])})

    # the hook did reword the logs: the runner's verdict line is there only backwards
    runner_log = (reworded["report"] / "runner.log").read_text()
    assert MARK + ".etelpmoc noissiM" in runner_log
    assert "Mission complete." not in runner_log
    assert MARK + "tes si lla_esufer :" in (reworded["report"] / "report.log").read_text()

    assert plain["code"] == 0, plain["out"]
    assert _verdict(reworded) == _verdict(plain)
    progress = _verdict(plain)[1]
    assert "Report for survivor_1 refused by base: refuse_all is set" in progress
    assert progress[-1] == "Mission complete."

    live = [_mission(read_json(run["report"] / "mission.json")) for run in (plain, reworded)]
    assert live[1] == live[0]
    assert live[0]["survivors"] == [("survivor_1", -2.5, 3.2, False, "refuse_all is set"),
                                    ("survivor_2", 4.1, -2.5, False, "refuse_all is set")]
    assert [f[:3] for f in live[0]["failures"]] == [("failure", "0.0.3.0.2", "NotifyBase")] * 2

    recorded = [_recorded(run["record"]) for run in (plain, reworded)]
    assert recorded[1][0] == recorded[0][0]
    kinds = [told[0] for told in recorded[0][0]]
    assert kinds.count(SarKind.ZONE_REACHED) == 4 and kinds[-1] == EventKind.COMPLETION
    assert SarKind.SURVIVOR_REFUSED in kinds and EventKind.NOTE in kinds
    for (_, replayed), run in zip(recorded, (plain, reworded), strict=True):
        replayed.update(outcome="SUCCESS", reason="", root_status=None)
        expected = _mission(read_json(run["report"] / "mission.json"))
        expected["outcome"] = ("SUCCESS", "", None)
        assert _mission(replayed) == expected
    assert no_traceback(plain["out"]) and no_traceback(reworded["out"])
