"""Each robot on a "machine" of its own: Linux network namespaces joined by a bridge.

The simulator (the shared world) runs in host ``world``; each robot's runner in a host of
its own. DDS can reach the other hosts only over the lab's bridge, through static peers,
so a passing mission proves discovery and traffic crossed it (and the bridge's counters
show it). Needs root and ``ip netns``; the module skips with one line otherwise.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest
from sar_testing.netns import NetworkLab, machine_namespaces, netns_unavailable
from sar_testing.processes import NodeProcess

pytestmark = pytest.mark.ros

REPO = Path(__file__).resolve().parents[2]
SPAWNS = {"robot1": (0.5, 0.0, 1.57), "robot2": (2.0, 1.0, 0.0)}
PLAN = {"robot1": "zone_a", "robot2": "zone_b"}
VISIT_TREE = """\
format: 1
name: netns_visit
root:
  sequence:
    name: Visit
    memory: true
    children:
      - ZonesRemaining: {name: "ZonesRemaining?"}
      - NavigateToZone: {}
      - AdvanceZone: {}
"""


@pytest.fixture(scope="module")
def lab() -> Iterator[NetworkLab]:
    reason = netns_unavailable()
    if reason:
        pytest.skip(f"no network-namespace test: {reason}")
    with NetworkLab(["world", *SPAWNS]) as made:
        yield made


def test_robots_in_their_own_network_namespaces_reach_the_shared_simulator(
        lab: NetworkLab, tmp_path: Path) -> None:
    fleet = tmp_path / "fleet.yaml"
    fleet.write_text("robots:\n" + "".join(
        f"  - name: {name}\n    pose: {{x: {x}, y: {y}, yaw: {yaw}}}\n"
        for name, (x, y, yaw) in SPAWNS.items()), encoding="utf-8")
    tree = tmp_path / "visit.yaml"
    tree.write_text(VISIT_TREE, encoding="utf-8")
    before = lab.bridge_bytes()
    sim_args = ["-m", "sar_framework.sim", "--ros-args", "-p", "speed:=30.0",
                "-p", f"fleet_file:={fleet}"]
    with NodeProcess(sim_args, "sim", log_dir=tmp_path, prefix=lab.enter("world"),
                     env=lab.ros_env("world")) as sim:
        sim.wait_for_output("ready", timeout=30)
        runners = []
        for name, (x, y, _) in SPAWNS.items():
            args = ["-m", "sar_framework.runner.node", "--ros-args", "-r", f"__ns:=/{name}",
                    "--params-file", str(REPO / "config" / "mission_params.yaml"),
                    "-p", f"tree:={tree}", "-p", f"zone_order:=[{PLAN[name]}]",
                    "-p", f"initial_pose.x:={x}", "-p", f"initial_pose.y:={y}",
                    "-p", "exit_on_completion:=true", "-p", "tick_rate_hz:=10.0"]
            runners.append(NodeProcess(args, f"runner_{name}", log_dir=tmp_path,
                                       prefix=lab.enter(name), env=lab.ros_env(name)).start())
        try:
            codes = [runner.wait(timeout=90.0) for runner in runners]
        finally:
            for runner in runners:
                runner.stop()
    assert codes == [0, 0], "\n".join(r.output for r in runners)
    for runner, zone in zip(runners, PLAN.values(), strict=True):
        assert f"Reached {zone}." in runner.output
    crossed = lab.bridge_bytes() - before
    assert crossed > 1_000_000  # the robots' traffic crossed the bridge (about 5 MB)


def test_the_lab_leaves_nothing_behind() -> None:
    reason = netns_unavailable()
    if reason:
        pytest.skip(f"no network-namespace test: {reason}")
    with NetworkLab(["a", "b"]) as lab:
        made = set(lab.namespaces())
        assert made <= machine_namespaces()
    assert not made & machine_namespaces()
