"""Each robot on a "machine" of its own: Linux network namespaces joined by a bridge.

The fleet mission (:mod:`fleet_mission`) with the simulator, the base and the coordinator
on host ``world`` and each robot's detect server and runner on a host of its own. DDS can
reach the other hosts only over the lab's bridge, through static peers, so a passing
mission proves discovery and traffic crossed it (and the bridge's counters show it). Needs
root and ``ip netns``; the module skips with one line otherwise. Two robots on two hosts
show it as well as three.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from fleet_mission import ZONES, run_fleet
from sar_testing.netns import NetworkLab, machine_namespaces, netns_unavailable

pytestmark = pytest.mark.ros

ROBOTS = ("robot1", "robot2")


@pytest.fixture(autouse=True)
def _needs_netns() -> None:
    reason = netns_unavailable()
    if reason:
        pytest.skip(f"no network-namespace test: {reason}")


def test_a_fleet_on_hosts_of_its_own_searches_every_zone_over_the_bridge(
        tmp_path: Path) -> None:
    with NetworkLab(["world", *ROBOTS]) as lab:
        before = lab.bridge_bytes()
        run = run_fleet(tmp_path, lab=lab, robots=ROBOTS)
        crossed = lab.bridge_bytes() - before
    assert run.codes == dict.fromkeys(ROBOTS, 0), run.outputs
    searched = run.searched()
    assert sorted(searched) == sorted(ZONES), run.outputs
    assert all(len(robots) == 1 for robots in searched.values()), searched
    ids = [r["survivor_id"] for r in run.reports or []]
    assert len(ids) == len(set(ids)) == 2, run.outputs  # the table's two survivors, once
    assert crossed > 1_000_000  # the robots' traffic crossed the bridge (megabytes)


def test_the_lab_leaves_nothing_behind() -> None:
    with NetworkLab(["a", "b"]) as lab:
        made = set(lab.namespaces())
        assert made <= machine_namespaces()
    assert not made & machine_namespaces()
