"""Three robots share the zones by auction over real DDS (issue 23, points 3 and 5).

Each test runs the whole fleet (:mod:`fleet_mission`): the simulator, the coordinator,
per robot a runner of trees/fleet_search.yaml. The verdict comes from the coordinator's
events file: every zone searched exactly once, every runner finished (home); and the
base's report file: every survivor reported once, under its fleet-wide id.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from fleet_mission import ZONES, run_fleet

pytestmark = pytest.mark.ros


def test_three_robots_search_every_zone_once_and_go_home(tmp_path: Path) -> None:
    run = run_fleet(tmp_path)
    assert run.codes == {"robot1": 0, "robot2": 0, "robot3": 0}, run.outputs
    searched = run.searched()
    assert sorted(searched) == sorted(ZONES), run.outputs
    assert all(len(robots) == 1 for robots in searched.values()), searched
    assert len({robots[0] for robots in searched.values()}) >= 2  # the work was shared
    assert run.kinds("complete"), run.outputs
    # Survivors counted once: each of the table's two survivors reported once, by its id.
    reported = sorted((r["survivor_id"], round(r["x"], 2), round(r["y"], 2))
                      for r in run.reports or [])
    registered = {e["survivor_id"] for e in run.kinds("survivor_registered")}
    assert sorted(p[1:] for p in reported) == [(-2.5, 3.2), (4.1, -2.5)], run.outputs
    assert {r[0] for r in reported} == registered == {"survivor_1", "survivor_2"}
    bids = run.kinds("bid")
    assert bids and all(len(b["zone_ids"]) == len(b["costs"]) for b in bids)
    for award in run.kinds("award"):  # the winner bid the lowest among the round's bids
        same = [b for b in bids if b["auction_id"] == award["auction_id"]
                and award["zone_id"] in b["zone_ids"]]
        mine = next(b for b in same if b["robot"] == award["robot"])
        cost = mine["costs"][mine["zone_ids"].index(award["zone_id"])]
        assert cost == pytest.approx(award["costs"][0])


def test_a_zone_one_robot_cannot_reach_is_given_back_and_searched_by_another(
        tmp_path: Path) -> None:
    # The simulator aborts each robot's first navigate_to_pose goal: each robot gives its
    # first zone back, and another robot takes it.
    run = run_fleet(tmp_path, sim_params=["-p", "abort_goal_numbers:=[1]"])
    given: dict[str, set[str]] = {}
    for event in run.kinds("given_back"):
        given.setdefault(event["zone_id"], set()).add(event["robot"])
    assert given, run.outputs
    searched = run.searched()
    assert all(len(robots) == 1 for robots in searched.values()), searched
    taken_over = [z for z, robots in given.items() if searched.get(z, [""])[0] not in robots]
    assert taken_over, (given, searched)
    for zone in set(ZONES) - set(searched):  # only when every robot gave it back
        assert given.get(zone) == {"robot1", "robot2", "robot3"}, run.outputs
        assert zone in {e["zone_id"] for e in run.kinds("abandoned")}
    assert run.codes == {"robot1": 0, "robot2": 0, "robot3": 0}, run.outputs
