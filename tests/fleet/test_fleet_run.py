"""``sar-tree run trees/fleet_search.yaml --robots 2``: the whole fleet from one command.

Real processes over real DDS (the test's leased domain): one simulator, the base, the zone
coordinator, and per robot a detect server and a runner in ``/robotN``. The verdicts come
from events: every robot's, and the fleet's (every zone searched once by the coordinator's
``searched`` events, every robot home, each auction won by its lowest bid); and from the
base's report file: every survivor reported once, under its fleet-wide id. A tree that
uses no app runs named robots on the core alone.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from sar_framework.events.event import EventKind
from sar_framework.events.jsonl import EVENTS_FILE, read_events

pytestmark = pytest.mark.ros

REPO = Path(__file__).resolve().parents[2]


def test_two_robots_share_the_zones_and_come_home(tmp_path: Path) -> None:
    report = tmp_path / "run"
    result = subprocess.run(
        [sys.executable, "-m", "sar_framework", "run", "trees/fleet_search.yaml",
         "--robots", "2", "--speed", "30", "--timeout", "240", "--report-dir", str(report)],
        capture_output=True, text=True, timeout=300, cwd=REPO, check=False)
    out = result.stdout + result.stderr
    assert result.returncode == 0, out
    assert "Traceback" not in out
    fleet = json.loads((report / "fleet.json").read_text())
    assert fleet["outcome"] == "SUCCESS" and fleet["coordinator"] is True
    assert sorted(fleet["robots"]) == ["robot1", "robot2"]
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
    assert len(set().union(*searchers.values())) >= 2  # the work was shared
    assert_each_award_went_to_the_lowest_bid(coordinator)
    # Survivors counted once: each of the table's two survivors reported once, by its id.
    reports = [json.loads(line) for line in
               (report / "reports.jsonl").read_text().splitlines() if line.strip()]
    assert sorted((round(r["x"], 2), round(r["y"], 2)) for r in reports) == [
        (-2.5, 3.2), (4.1, -2.5)], out
    registered = {e["survivor_id"] for e in coordinator if e["kind"] == "survivor_registered"}
    assert {r["survivor_id"] for r in reports} == registered == {"survivor_1", "survivor_2"}
    assert (report / "fleet.png").stat().st_size > 0
    assert "sar-tree run: Fleet SUCCESS" in result.stdout


def assert_each_award_went_to_the_lowest_bid(events: list[dict[str, Any]]) -> None:
    """Every bid prices each zone it names; each award's cost is the winner's own bid."""
    bids = [e for e in events if e["kind"] == "bid"]
    assert bids and all(len(b["zone_ids"]) == len(b["costs"]) for b in bids)
    for award in (e for e in events if e["kind"] == "award"):
        mine = next(b for b in bids if b["auction_id"] == award["auction_id"]
                    and b["robot"] == award["robot"] and award["zone_id"] in b["zone_ids"])
        cost = mine["costs"][mine["zone_ids"].index(award["zone_id"])]
        assert cost == pytest.approx(award["costs"][0])


def test_a_fleet_cut_short_by_the_timeout_says_which_robots_were_still_running(
        tmp_path: Path) -> None:
    # The timeout is the orchestrator's, for any tree: a tree that never ends, and no app's
    # processes (the search's coordinator, detect and report servers) to start for it.
    folder = tmp_path / "forever"
    folder.mkdir()
    (folder / "forever.yaml").write_text(COUNT_FOREVER, encoding="utf-8")
    report = folder / "run"
    result = subprocess.run(
        [sys.executable, "-m", "sar_framework", "run", "forever.yaml",
         "--robots", "2", "--timeout", "4", "--report-dir", str(report)],
        capture_output=True, text=True, timeout=120, cwd=folder, check=False)
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


COUNT = """\
format: 1
name: count
description: Counts once; uses no app.
blackboard:
  laps: {type: int, initial: 0, description: laps}
root:
  sequence:
    name: Count
    memory: true
    children:
      - Script: {name: CountOnce, code: "laps += 1"}
"""

COUNT_FOREVER = """\
format: 1
name: count_forever
description: Counts for ever; uses no app.
blackboard:
  laps: {type: int, initial: 0, description: laps}
root:
  sequence:
    name: CountForever
    memory: true
    children:
      - success_is_running: {child: {Script: {name: CountAgain, code: "laps += 1"}}}
"""


def test_named_robots_of_a_tree_that_uses_no_app(tmp_path: Path) -> None:
    folder = tmp_path / "count"
    folder.mkdir()
    (folder / "count.yaml").write_text(COUNT, encoding="utf-8")
    result = subprocess.run(
        [sys.executable, "-m", "sar_framework", "run", "count.yaml", "--robots", "2",
         "--speed", "30", "--timeout", "240", "--report-dir", "out"],
        capture_output=True, text=True, timeout=300, cwd=folder, check=False)
    out = result.stdout + result.stderr
    assert result.returncode == 0, out
    report = folder / "out"
    fleet = json.loads((report / "fleet.json").read_text())
    assert fleet["outcome"] == "SUCCESS", fleet
    assert {name: r["outcome"] for name, r in fleet["robots"].items()} == {
        "robot1": "SUCCESS", "robot2": "SUCCESS"}
    assert "coordinator" not in fleet and "zones" not in fleet  # no app, no app's keys
    for name in ("robot1", "robot2"):
        assert json.loads((report / name / "mission.json").read_text())["outcome"] == "SUCCESS"
    # the simulator and a runner per robot, nothing else (no app's processes)
    logs = sorted(str(p.relative_to(report)) for p in report.rglob("*.log")
                  if p.parent.name != "ros_log" and "ros_log" not in p.parts)
    assert logs == ["robot1/runner.log", "robot2/runner.log", "sim.log"], logs
    assert "sar-tree run: Fleet SUCCESS" in result.stdout
