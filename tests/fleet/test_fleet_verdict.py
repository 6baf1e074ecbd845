"""Named robots' verdict and picture from events and reports (no ROS): good and bad fleets.

The core's verdict (each robot's) and the search-and-rescue app's problems (zones searched
once, robots home), as ``sar-tree run`` combines them.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from sar_plugins.sar.app import APP
from sar_plugins.sar.fleet.report import award_lines, zone_problems, zone_searchers

from sar_framework.events.jsonl import read_json_lines
from sar_framework.mission.processes import MissionSettings, Robot
from sar_framework.orchestrate.outcome import Outcome, robots_outcome
from sar_framework.report_robots import ROBOT_COLOURS, app_findings, draw_fleet, fleet_document

REPO = Path(__file__).resolve().parents[2]
ZONES = ["zone_a", "zone_b"]
OK = Outcome("SUCCESS", 0)


def _summary(*zones: str, home: bool = True) -> dict:
    return {"zones_visited": [{"id": z} for z in zones], "at_base": home,
            "final_position": {"x": 1.0, "y": 2.0}, "sim_duration_s": 50.0}


def fleet_outcome(robots: dict[str, Outcome], summaries: dict[str, Any],
                  searched: dict[str, list[str]], *, once: bool) -> Outcome:
    """The verdict ``sar-tree run`` gives: the robots', with the app's problems."""
    own = {name: {**summary, "outcome": robots[name].status}
           for name, summary in summaries.items()}
    return robots_outcome(robots, zone_problems(searched, own, once=once))


def _events(*records: dict) -> list[dict]:
    return [{"seq": i, "robot": "", "zone_id": "", "zone_ids": [], "costs": [], **r}
            for i, r in enumerate(records, 1)]


SEARCHED = _events({"kind": "searched", "robot": "robot1", "zone_id": "zone_a"},
                   {"kind": "searched", "robot": "robot2", "zone_id": "zone_b"})


def test_every_zone_searched_once_and_every_robot_home_is_success() -> None:
    summaries = {"robot1": _summary("zone_a"), "robot2": _summary("zone_b")}
    searched = zone_searchers(ZONES, summaries, SEARCHED)
    assert searched == {"zone_a": ["robot1"], "zone_b": ["robot2"]}
    assert fleet_outcome({"robot1": OK, "robot2": OK}, summaries, searched, once=True) == OK


def test_a_zone_searched_twice_never_or_a_robot_away_fails_the_fleet() -> None:
    events = [*SEARCHED, *_events({"kind": "searched", "robot": "robot2", "zone_id": "zone_a"})]
    summaries = {"robot1": _summary("zone_a"), "robot2": _summary("zone_b", home=False)}
    searched = zone_searchers([*ZONES, "zone_c"], summaries, events)
    verdict = fleet_outcome({"robot1": OK, "robot2": OK}, summaries, searched, once=True)
    assert (verdict.status, verdict.exit_code) == ("FAILURE", 1)
    assert verdict.reason == ("zone_a was searched 2 times (robot1, robot2); zone_c was never "
                              "searched; robot2 is not home (ends at (1.00, 2.00))")


def test_a_robot_s_own_verdict_decides_and_an_interrupt_wins() -> None:
    summaries = {"robot1": _summary("zone_a", "zone_b"), "robot2": _summary("zone_a", "zone_b")}
    searched = zone_searchers(ZONES, summaries, None)  # no coordinator: each walks them all
    assert searched == {"zone_a": ["robot1", "robot2"], "zone_b": ["robot1", "robot2"]}
    assert fleet_outcome({"robot1": OK, "robot2": OK}, summaries, searched, once=False) == OK
    failed = Outcome("FAILURE", 1, "NavigateToZone [0.1] failed: blocked")
    verdict = fleet_outcome({"robot1": OK, "robot2": failed}, summaries, searched, once=False)
    assert verdict.reason == "robot2: FAILURE (NavigateToZone [0.1] failed: blocked)"
    stopped = Outcome("INTERRUPTED", 130, "interrupted (Ctrl-C)")
    assert fleet_outcome({"robot1": stopped, "robot2": failed}, summaries, searched,
                         once=False).exit_code == 130


def test_the_events_file_tolerates_a_line_cut_by_a_kill(tmp_path: Path) -> None:
    path = tmp_path / "fleet_events.jsonl"
    path.write_text('{"kind": "searched", "robot": "r", "zone_id": "z"}\n[1]\n{"kind": "se')
    assert read_json_lines(path) == [{"kind": "searched", "robot": "r", "zone_id": "z"}]
    assert read_json_lines(tmp_path / "none.jsonl") == []


BIDS = _events(
    {"kind": "auction", "auction_id": 1, "zone_ids": ZONES},
    {"kind": "bid", "auction_id": 1, "robot": "robot1", "zone_ids": ZONES, "costs": [2.5, 7.0]},
    {"kind": "bid", "auction_id": 1, "robot": "robot2", "zone_ids": ZONES, "costs": [6.0, None]},
    {"kind": "award", "auction_id": 1, "robot": "robot1", "zone_id": "zone_a", "costs": [2.5]},
    {"kind": "robot_lost", "robot": "robot2", "message": "silent for 3 s"},
    {"kind": "award", "auction_id": 2, "robot": "robot1", "zone_id": "zone_b", "costs": [4.0]})


def test_the_picture_s_lines_give_each_award_with_its_round_s_bids() -> None:
    assert award_lines(BIDS) == [
        "#1 zone_a -> robot1 2.5 m", "   robot1: zone_a 2.5, zone_b 7.0",
        "   robot2: zone_a 6.0, zone_b -", "robot2 lost: silent for 3 s",
        "#2 zone_b -> robot1 4.0 m"]


def test_fleet_png_draws_each_robot_s_path_in_its_colour(tmp_path: Path) -> None:
    from PIL import Image

    for name, (x0, y0) in (("robot1", (-2.0, -1.0)), ("robot2", (2.0, 2.0))):
        (tmp_path / name).mkdir()
        lines = [{"event": "start", "x": x0, "y": y0}] + [
            {"sim_s": i, "x": x0 + 0.1 * i, "y": y0} for i in range(1, 10)]
        (tmp_path / name / "trace.jsonl").write_text(
            "".join(json.dumps(line) + "\n" for line in lines))
    planned = [{"id": z, "x": x, "y": 3.0} for z, x in
               (("zone_a", -3.0), ("zone_b", 3.5), ("zone_c", 4.0), ("zone_d", -3.5))]
    summaries = {"robot1": {**_summary("zone_a"), "zones_planned": planned},
                 "robot2": {**_summary("zone_b"), "zones_planned": planned}}
    for name, summary in summaries.items():
        (tmp_path / name / "mission.json").write_text(json.dumps(summary))
    (tmp_path / "fleet_events.jsonl").write_text(
        "".join(json.dumps(e) + "\n" for e in [*BIDS, *SEARCHED]))
    settings = MissionSettings("t.yaml", run_folder=str(tmp_path),
                               robots=(Robot("robot1"), Robot("robot2")),
                               node_kinds=frozenset({"ClaimZone"}))
    keys, problems = app_findings(settings, summaries, [APP])
    assert problems == ["zone_c was never searched", "zone_d was never searched"]
    document = fleet_document("FAILURE", "; ".join(problems), {"robot1": OK, "robot2": OK},
                              summaries, keys, wall_duration_s=10.0)
    out = draw_fleet(tmp_path, document, [APP], tmp_path / "fleet.png")
    colours = {colour for _count, colour in Image.open(out).convert("RGB").getcolors(1 << 20)}
    assert set(ROBOT_COLOURS[:2]) <= colours
    assert document["coordinator"] is True
    assert document["zones"]["zone_c"] == {"searched_by": []}
    assert document["robots"]["robot2"]["report"] == "robot2/mission.json"
    assert document["robots"]["robot1"]["zones_visited"] == ["zone_a"]


def test_robots_without_an_app_succeed_on_their_own_verdicts(tmp_path: Path) -> None:
    settings = MissionSettings("t.yaml", run_folder=str(tmp_path), robots=(Robot("a"),))
    keys, problems = app_findings(settings, {"a": {"goals": []}}, [APP])
    assert (keys, problems) == ({}, [])
    assert robots_outcome({"a": OK}, problems) == OK
