"""A server or the simulator killed mid-mission: the tree sees it, as it would on a robot.

A server's death is a service that stops answering: the leaf fails with that reason after
its bound, and a tree written to skip goes on (regression: the supervisor aborted the whole
run, quoting the server's last log line). The simulator is the clock: its death ends the
run, naming the process and the signal. Nothing reported is lost, no process is left.

Two kills share one run where their facts stay apart: the report server killed once
survivor_1 is reported (survivor_2's report fails at zone_c), then the detect server on the
way to the last zone (zone_d's detection fails).
"""

from __future__ import annotations

import os
import signal
from pathlib import Path

import pytest

from .helpers import (
    FAST,
    SKIP_TREE,
    child_pids,
    no_traceback,
    read_json,
    read_jsonl,
    sar_tree_run,
    wait_gone,
)

pytestmark = [pytest.mark.slow, pytest.mark.ros]

MODULES = {"detect": "detect_survivor_server", "report": "report_survivor_server",
           "sim": "sar_framework.sim"}


def _quick_service_bounds(tmp_path: Path) -> Path:
    """The skip tree with 3 s service bounds (the defaults are 10 s).

    The bounds count ROS time, the simulator's; an answer that is late or lost is sent again
    after the wall-time resend interval, and a bound fails a call only after that resend
    (``leaves/service_call.py``). So a killed server is noticed soon, and a live one on a
    loaded machine still answers within its bound.
    """
    bounds = "server_timeout_s: 3.0, response_timeout_s: 3.0"
    text = SKIP_TREE.read_text().replace("DetectSurvivor: {id: detect}",
                                         f"DetectSurvivor: {{id: detect, {bounds}}}")
    text = text.replace("NotifyBase: {detector: detect, broadcaster: broadcast}",
                        f"NotifyBase: {{detector: detect, broadcaster: broadcast, {bounds}}}")
    tree = tmp_path / "skip_quick.yaml"
    tree.write_text(text)
    return tree


def _pid_of(parent: int, label: str) -> int:
    for pid in child_pids(parent):
        cmdline = Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode()
        if MODULES[label] in cmdline and "--ros-args" in cmdline:
            return pid
    raise AssertionError(f"no {label} child of {parent}")


def _kill_when(tmp_path: Path, *kills: tuple[str, str]) -> tuple[int, str, Path, list[int]]:
    """Run the quick skip tree; kill each ``(label, moment)``'s process once it printed moment."""
    report = tmp_path / "report"
    process = sar_tree_run([str(_quick_service_bounds(tmp_path)), "--speed", FAST,
                            "--timeout", "90"], report)
    try:
        children = []
        for label, moment in kills:
            process.wait_for_output(moment, timeout=60)
            children = children or child_pids(process.pid)
            os.kill(_pid_of(process.pid, label), signal.SIGKILL)
        code = process.wait(timeout=90)
    finally:
        process.stop()
    return code, process.output, report, children


@pytest.fixture(scope="module")
def report_then_detect_killed(tmp_path_factory: pytest.TempPathFactory
                              ) -> tuple[int, str, Path, list[int]]:
    """One run, two faults that do not touch each other's facts: the report server killed
    once survivor_1 is reported (survivor_2's report at zone_c then fails), the detect
    server killed on the way to the last zone (its detection then fails)."""
    return _kill_when(tmp_path_factory.mktemp("two_killed"),
                      ("report", r"Report received: survivor_1"),
                      ("detect", r"--- Zone 4/4: zone_d"))


def _check_detect_killed(code: int, out: str, report: Path, children: list[int]) -> None:
    assert code == 0, out
    assert "the detect process was killed by SIGKILL mid-mission; the tree goes on" in out
    assert "DetectSurvivor [" in out and "/detect_survivor" in out  # the leaf's reason line
    assert " skip: VisitZone failed (" in out
    assert "Mission complete." in out and no_traceback(out)
    mission = read_json(report / "mission.json")
    assert mission["base_reached"] is not None and mission["at_base"] is True
    # what was acknowledged before the kill is in the report
    acknowledged = [s["id"] for s in mission["survivors"] if s.get("acknowledged")]
    assert acknowledged == [r["survivor_id"] for r in read_jsonl(report / "reports.jsonl")]
    assert wait_gone(children) == []


@pytest.mark.parametrize("moment", [r"--- Zone 1/4: zone_a", r"Report received: survivor_1"])
def test_detect_server_killed_the_tree_skips_and_finishes(tmp_path: Path, moment: str) -> None:
    _check_detect_killed(*_kill_when(tmp_path, ("detect", moment)))


def test_detect_server_killed_before_the_last_zone_the_tree_skips_and_finishes(
        report_then_detect_killed: tuple[int, str, Path, list[int]]) -> None:
    _check_detect_killed(*report_then_detect_killed)


def test_report_server_killed_mid_mission_the_tree_goes_on(
        report_then_detect_killed: tuple[int, str, Path, list[int]]) -> None:
    code, out, report, children = report_then_detect_killed
    assert code == 0, out
    assert "the report process was killed by SIGKILL mid-mission" in out
    assert "NotifyBase [" in out
    assert [r["survivor_id"] for r in read_jsonl(report / "reports.jsonl")] == ["survivor_1"]
    assert wait_gone(children) == []


@pytest.mark.parametrize("moment", [r"--- Zone 1/4: zone_a", r"Reached zone_b\."])
def test_simulator_killed_ends_the_run_naming_it(tmp_path: Path, moment: str) -> None:
    code, out, report, children = _kill_when(tmp_path, ("sim", moment))
    assert code == 1, out
    assert ("the sim process was killed by SIGKILL mid-mission; simulated time stopped, "
            "so the tree cannot go on") in out
    assert "Mission ERROR" in out and no_traceback(out)
    assert (report / "mission.json").exists()
    assert wait_gone(children) == []
