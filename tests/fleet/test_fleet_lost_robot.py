"""A robot's runner SIGKILLed mid-mission: the coordinator notices, its zone is taken over.

Three moments: right after the robot won a zone (it holds a claim and has not arrived),
while it searches its zone (the detect servers answer 1 s late), and right after it
searched a zone, asking for work between zones. The first two share one run of three
robots, of which two are killed; the third runs two robots, one killed. The coordinator
must report the robot lost (after ``robot_timeout_wall_s`` of silence; how soon is not
checked here), put the zone it held back to auction, and every zone must still be searched
exactly once.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from fleet_mission import ZONES, run_fleet

pytestmark = pytest.mark.ros


def after_award(events: list[dict[str, Any]], outputs: dict[str, str]) -> str | None:
    awards = [e for e in events if e["kind"] == "award" and e["robot"] in outputs]
    return awards[0]["robot"] if awards else None


def mid_search(events: list[dict[str, Any]], outputs: dict[str, str]) -> str | None:
    searched = {e["zone_id"] for e in events if e["kind"] == "searched"}
    for award in (e for e in events if e["kind"] == "award"):
        zone = award["zone_id"]
        if zone not in searched and f"Reached {zone}." in outputs.get(award["robot"], ""):
            return award["robot"]
    return None


def between_zones(events: list[dict[str, Any]], outputs: dict[str, str]) -> str | None:
    searched = [e for e in events if e["kind"] == "searched" and e["robot"] in outputs]
    return searched[0]["robot"] if searched and len(searched) < len(ZONES) else None


#: Whether the robot holds a claim when it is killed at that moment.
HOLDS_A_CLAIM = {after_award: True, mid_search: True, between_zones: False}


# Two moments share a run (three robots: two killed, one finishes the mission), the third
# has its own: asking for work between zones must come before every zone is searched (two
# robots: one killed, one finishes).
@pytest.mark.parametrize(("moments", "robots"), [
    ((after_award, mid_search), ("robot1", "robot2", "robot3")),
    ((between_zones,), ("robot1", "robot2"))],
    ids=["claimed_before_arriving_and_mid_search", "asking_for_work_between_zones"])
def test_a_killed_robots_zone_is_taken_over(tmp_path: Path, moments: tuple[Any, ...],
                                            robots: tuple[str, ...]) -> None:
    run = run_fleet(tmp_path, kill=moments, detect_params=["-p", "answer_delay_wall_s:=1.0"],
                    robots=robots)
    searched = run.searched()
    for moment, victim in zip(moments, run.victims, strict=True):
        assert victim is not None, f"the moment {moment.__name__} never came\n{run.outputs}"
        lost = next((e for e in run.kinds("robot_lost") if e["robot"] == victim), None)
        assert lost is not None, f"{victim} killed, never reported lost\n{run.outputs}"
        if HOLDS_A_CLAIM[moment]:
            assert lost["zone_ids"], (moment.__name__, lost)
            for zone in lost["zone_ids"]:  # back to auction, among the live robots only
                again = [a for a in run.kinds("auction")
                         if zone in a["zone_ids"] and a["seq"] > lost["seq"]]
                assert again and victim not in again[0]["robots"], (moment.__name__, again)
                # Searched by another robot, even when the dead robot's body stands on the
                # zone's pose (killed there): the planner's tolerance ends the path beside it.
                assert searched.get(zone, [""])[0] not in ("", *run.victims), run.outputs
    assert not run.kinds("abandoned"), run.outputs
    assert sorted(searched) == sorted(ZONES), run.outputs
    assert all(len(robots) == 1 for robots in searched.values()), searched
    survivors = {n: c for n, c in run.codes.items() if n not in run.victims}
    assert survivors and all(c == 0 for c in survivors.values()), run.outputs
