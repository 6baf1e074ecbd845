"""``sar-tree run trees/fleet_search.yaml --robots 3``: the whole fleet from one command.

Real processes over real DDS (the test's leased domain): one simulator, the base, the zone
coordinator, and per robot a detect server and a runner in ``/robotN``. The verdicts come
from events: every robot's, and the fleet's (every zone searched once by the coordinator's
``searched`` events, every robot home).
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from sar_framework.events.event import EventKind
from sar_framework.events.jsonl import EVENTS_FILE, read_events

pytestmark = pytest.mark.ros

REPO = Path(__file__).resolve().parents[2]


def test_three_robots_share_the_zones_and_come_home(tmp_path: Path) -> None:
    report = tmp_path / "run"
    result = subprocess.run(
        [sys.executable, "-m", "sar_framework", "run", "trees/fleet_search.yaml",
         "--robots", "3", "--speed", "30", "--timeout", "240", "--report-dir", str(report)],
        capture_output=True, text=True, timeout=300, cwd=REPO, check=False)
    out = result.stdout + result.stderr
    assert result.returncode == 0, out
    assert "Traceback" not in out
    fleet = json.loads((report / "fleet.json").read_text())
    assert fleet["outcome"] == "SUCCESS" and fleet["coordinator"] is True
    assert sorted(fleet["robots"]) == ["robot1", "robot2", "robot3"]
    searchers = {zone: z["searched_by"] for zone, z in fleet["zones"].items()}
    assert sorted(searchers) == ["zone_a", "zone_b", "zone_c", "zone_d"]
    assert all(len(by) == 1 for by in searchers.values()), searchers
    for name, robot in fleet["robots"].items():
        assert robot["outcome"] == "SUCCESS" and robot["at_base"] is True, (name, robot)
        mission = json.loads((report / name / "mission.json").read_text())
        assert [z["id"] for z in mission["zones_visited"]] == [
            zone for zone, by in searchers.items() if by == [name]] or mission["zones_visited"]
        events = read_events(report / name / EVENTS_FILE)
        assert events[-1].kind == EventKind.VERDICT and events[-1].status == "SUCCESS"
        assert (report / name / "mission.png").stat().st_size > 0
    coordinator = [json.loads(line) for line in
                   (report / "fleet_events.jsonl").read_text().splitlines()]
    assert {e["kind"] for e in coordinator} >= {"robot_joined", "auction", "bid", "award",
                                                "searched", "complete"}
    assert (report / "fleet.png").stat().st_size > 0
    assert "sar-tree run: Fleet SUCCESS" in result.stdout


def test_a_fleet_cut_short_by_the_timeout_says_which_robots_were_still_running(
        tmp_path: Path) -> None:
    report = tmp_path / "run"
    result = subprocess.run(
        [sys.executable, "-m", "sar_framework", "run", "trees/fleet_search.yaml",
         "--robots", "2", "--timeout", "4", "--report-dir", str(report)],
        capture_output=True, text=True, timeout=120, cwd=REPO, check=False)
    out = result.stdout + result.stderr
    assert result.returncode == 1, out
    assert "Traceback" not in out
    fleet = json.loads((report / "fleet.json").read_text())
    assert fleet["outcome"] == "TIMEOUT"
    assert fleet["reason"].startswith("timeout after 4 s; still running: robot1, robot2")
    assert {r["outcome"] for r in fleet["robots"].values()} == {"TIMEOUT"}
    for name in ("robot1", "robot2"):  # each robot's stream is closed with its verdict
        events = read_events(report / name / EVENTS_FILE)
        assert events and events[-1].kind == EventKind.VERDICT
        assert events[-1].status == "TIMEOUT"
    assert "sar-tree run: Fleet TIMEOUT" in result.stdout
