"""A zone one robot cannot reach goes to another, over real DDS.

The test runs the whole fleet (:mod:`fleet_mission`): the simulator, the coordinator, per
robot a runner of trees/fleet_search.yaml. The verdict comes from the coordinator's events
file. The fleet's plain mission (every zone searched once, the lowest bids winning,
survivors reported once) is checked on ``sar-tree run --robots 2`` (test_fleet_run.py).
Two robots are enough to give a zone back and take it over, so the test runs two.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from fleet_mission import ZONES, run_fleet

pytestmark = pytest.mark.ros

ROBOTS = ("robot1", "robot2")


def test_a_zone_one_robot_cannot_reach_is_given_back_and_searched_by_another(
        tmp_path: Path) -> None:
    # The simulator aborts each robot's first navigate_to_pose goal: each robot gives its
    # first zone back, and another robot takes it.
    run = run_fleet(tmp_path, sim_params=["-p", "abort_goal_numbers:=[1]"], robots=ROBOTS)
    given: dict[str, set[str]] = {}
    for event in run.kinds("given_back"):
        given.setdefault(event["zone_id"], set()).add(event["robot"])
    assert given, run.outputs
    searched = run.searched()
    assert all(len(robots) == 1 for robots in searched.values()), searched
    taken_over = [z for z, robots in given.items() if searched.get(z, [""])[0] not in robots]
    assert taken_over, (given, searched)
    for zone in set(ZONES) - set(searched):  # only when every robot gave it back
        assert given.get(zone) == set(ROBOTS), run.outputs
        assert zone in {e["zone_id"] for e in run.kinds("abandoned")}
    assert run.codes == dict.fromkeys(ROBOTS, 0), run.outputs
