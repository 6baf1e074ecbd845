"""``sar-tree run --robots N`` / ``--fleet FILE``: bad input refused, the processes described.

No ROS process starts here: the bad paths end before anything starts (exit 2, every
problem at once, no traceback; the command's ``main`` in this process), and the fleet's
process list is checked as data.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path

import pytest
from sar_plugins.sar.fleet.processes import (
    COORDINATOR_EVENTS_FILE,
    COORDINATOR_MODULE,
    rotated,
    uses_coordinator,
)

from sar_framework.cli import main
from sar_framework.mission.processes import MissionSettings, Robot
from sar_framework.orchestrate.config import check_config, child_specs
from sar_framework.orchestrate.options import RunConfig
from sar_framework.sim.occupancy import load_map
from sar_framework.sim.params import DEFAULT_MAP_YAML
from sar_framework.sim.spawn_poses import MAX_ROBOTS, SpawnError, free_places, spawn_poses

REPO = Path(__file__).resolve().parents[2]
TREE = str(REPO / "trees" / "search_and_rescue.yaml")
PARAMS = str(REPO / "config" / "mission_params.yaml")
Rejected = Callable[..., str]
"""``rejected(*args)``: the stderr of ``sar-tree run ARGS``, refused as a usage error."""


@pytest.fixture
def rejected(capsys: pytest.CaptureFixture[str]) -> Rejected:
    """``sar-tree run ARGS`` in this process (the command's own ``main``); its stderr.

    Asserts the usage exit (2), no traceback and that nothing was started.
    """

    def run(*args: str) -> str:
        code = main(["run", *args])
        out, err = capsys.readouterr()
        assert code == 2, out + err
        assert "Traceback" not in out + err
        assert "sar-tree run:" not in out  # nothing was started
        return err

    return run


@pytest.mark.parametrize("count", ["0", "-1", str(MAX_ROBOTS + 1)])
def test_robots_out_of_range_is_refused(count: str, tmp_path: Path,
                                        rejected: Rejected) -> None:
    err = rejected(TREE, "--robots", count, "--report-dir", str(tmp_path / "r"))
    assert f"--robots must be between 1 and {MAX_ROBOTS}, got {count}" in err
    assert not (tmp_path / "r").exists()


def test_robots_that_is_not_a_number_is_refused(rejected: Rejected) -> None:
    err = rejected(TREE, "--robots", "three")
    assert "--robots: invalid int value: 'three'" in err


def test_robots_with_fleet_is_refused(tmp_path: Path, rejected: Rejected) -> None:
    fleet = tmp_path / "fleet.yaml"
    fleet.write_text("robots:\n  - name: a\n    pose: {x: 1.0, y: 1.0}\n")
    err = rejected(TREE, "--robots", "2", "--fleet", str(fleet))
    assert "--robots and --fleet: give one of them" in err


def test_a_fleet_file_error_is_shown_at_its_line_and_column(tmp_path: Path,
                                                            rejected: Rejected) -> None:
    fleet = tmp_path / "fleet.yaml"
    fleet.write_text("robots:\n  - name: robot1\n    pose: {x: 1.0, y: 1.0}\n"
                     "  - name: 2robot\n    pose: {x: 1.0, y: oops}\n")
    err = rejected(TREE, "--fleet", str(fleet))
    assert f"{fleet}:4:11: robots[1].name: expected a namespace name" in err
    assert f"{fleet}:5:23: robots[1].pose.y: expected a finite number, got 'oops'" in err
    assert "2 problems in the inputs; nothing was started" in err


def test_crowded_spawns_and_a_missing_fleet_file_are_refused(tmp_path: Path,
                                                             rejected: Rejected) -> None:
    fleet = tmp_path / "fleet.yaml"
    fleet.write_text("robots:\n  - name: a\n    pose: {x: 1.0, y: 1.0}\n"
                     "  - name: b\n    pose: {x: 1.2, y: 1.0}\n")
    err = rejected(TREE, "--fleet", str(fleet))
    assert f"{fleet}:4:5: robot 'b' spawns within 0.44 m (two footprints) of robot 'a' " \
        f"({fleet}:2:5)" in err
    assert "fleet file not found" in rejected(TREE, "--fleet", str(tmp_path / "none.yaml"))


def test_what_a_fleet_cannot_do_yet_is_refused_at_once(tmp_path: Path,
                                                       rejected: Rejected) -> None:
    err = rejected(TREE, "--robots", "2", "--record", str(tmp_path / "x.mcap"), "--watch",
                   "--keep-alive")
    assert "--record follows one robot's topics" in err
    assert "--watch follows one robot's topics" in err
    assert "--keep-alive: not with a fleet yet" in err


ZONES = [(-3.0, 3.0), (3.5, 3.0), (4.0, -3.0), (-3.5, -3.0)]


def test_spawn_poses_are_free_spaced_near_the_base_and_out_of_the_way() -> None:
    from sar_framework.sim.planner import GridPlanner
    from sar_framework.sim.spawn_poses import (
        MIN_BASE_DISTANCE_M,
        SEARCH_RADIUS_M,
        TRAFFIC_CLEARANCE_M,
    )

    grid = load_map(DEFAULT_MAP_YAML)
    free = free_places(grid, 0.22 + 0.5)
    poses = spawn_poses(MAX_ROBOTS, (0.0, 0.0), grid, 0.22, destinations=ZONES)
    assert len(poses) == MAX_ROBOTS
    planner = GridPlanner(grid, 0.22)
    paths = [planner.plan((0.0, 0.0), zone) for zone in ZONES]
    for i, pose in enumerate(poses):
        assert free[grid.world_to_cell(pose.x, pose.y)], pose
        assert MIN_BASE_DISTANCE_M <= math.hypot(pose.x, pose.y) <= SEARCH_RADIUS_M
        for other in poses[:i]:
            assert math.hypot(pose.x - other.x, pose.y - other.y) >= 1.0 - 1e-9
        for path in paths:  # waypoints of the way from the base to each zone
            assert all(math.hypot(pose.x - x, pose.y - y) >= TRAFFIC_CLEARANCE_M - 0.05
                       for x, y in path), (pose, path)
    assert spawn_poses(3, (0.0, 0.0), grid, 0.22, destinations=ZONES) == poses[:3]  # stable
    rooms = {(pose.x > 0, pose.y > 0) for pose in poses[:4]}
    assert len(rooms) == 4  # the first four spread over the four rooms
    with pytest.raises(SpawnError, match=r"only .* free spawn places"):
        spawn_poses(200, (0.0, 0.0), grid, 0.22)


def _specs(config: RunConfig, tmp_path: Path, coordinator: bool = False) -> dict[str, list[str]]:
    inputs = check_config(config)
    kinds = inputs.node_kinds | ({"ClaimZone"} if coordinator else set())
    specs = child_specs(config, tmp_path, inputs.places, apps=inputs.apps,
                        robots=inputs.robots, node_kinds=frozenset(kinds))
    return {s.label: [s.module, *s.ros_args] for s in specs}


def test_the_fleet_s_processes_from_one_description(tmp_path: Path) -> None:
    specs = _specs(RunConfig(tree=TREE, params=PARAMS, robots=3), tmp_path)
    assert list(specs) == ["sim", "report", "robot1/detect", "robot2/detect",
                           "robot3/detect", "robot1/runner", "robot2/runner", "robot3/runner"]
    assert f"fleet_file:={tmp_path / 'fleet.yaml'}" in specs["sim"]
    assert f"trace_file:={tmp_path / 'trace.jsonl'}" in specs["sim"]
    assert not any(a.startswith("__ns:=") for a in specs["report"])  # one base, the root
    runner = specs["robot2/runner"]
    assert runner[:3] == ["sar_framework.runner.node", "-r", "__ns:=/robot2"]
    assert specs["robot2/detect"][1:3] == ["-r", "__ns:=/robot2"]
    assert f"status_file:={tmp_path / 'robot2' / 'status.json'}" in runner
    assert {"initial_pose.x:=4.0", "initial_pose.y:=1.0", "base_station.x:=4.0",
            "base_station.y:=1.0"} <= set(runner)
    assert "zone_order:=['zone_b', 'zone_c', 'zone_d', 'zone_a']" in runner  # each starts elsewhere


def test_the_coordinator_starts_in_the_root_with_the_mission_parameters(tmp_path: Path
                                                                        ) -> None:
    specs = _specs(RunConfig(tree=TREE, params=PARAMS, robots=2), tmp_path, coordinator=True)
    assert list(specs)[:3] == ["sim", "report", "coordinator"]
    assert specs["coordinator"] == [
        COORDINATOR_MODULE, "--params-file", PARAMS, "-p", "use_sim_time:=true",
        "-p", f"events_file:={tmp_path / COORDINATOR_EVENTS_FILE}",
        "-p", "robots:=['robot1', 'robot2']"]  # the first auction round waits for both
    assert not any(a.startswith("zone_order:=") for a in specs["robot1/runner"])


def test_a_fleet_file_names_the_robots(tmp_path: Path) -> None:
    fleet = tmp_path / "fleet.yaml"
    fleet.write_text("robots:\n  - name: scout\n    pose: {x: -1.0, y: -1.0, yaw: 1.57}\n")
    config = RunConfig(tree=TREE, params=PARAMS, fleet=str(fleet))
    assert check_config(config).robots == (Robot("scout", -1.0, -1.0, 1.57),)
    specs = _specs(config, tmp_path)
    assert f"fleet_file:={fleet}" in specs["sim"]
    assert "initial_pose.yaw:=1.57" in specs["scout/runner"]


def test_which_runs_need_the_coordinator() -> None:
    named = (Robot("robot1"), Robot("robot2"))
    assert uses_coordinator(MissionSettings("t", robots=named,
                                            node_kinds=frozenset({"Sequence", "ClaimZone"})))
    assert not uses_coordinator(MissionSettings("t", robots=named,
                                                node_kinds=frozenset({"NavigateToZone"})))
    assert not uses_coordinator(MissionSettings("t", node_kinds=frozenset({"ClaimZone"})))
    assert rotated(["a", "b", "c"], 4) == ["b", "c", "a"]


def test_one_robot_is_the_unnamed_robot_of_the_same_description(tmp_path: Path) -> None:
    specs = _specs(RunConfig(tree=TREE, params=PARAMS), tmp_path)
    assert list(specs) == ["sim", "detect", "report", "runner"]
    assert not any(a.startswith(("fleet_file:=", "__ns:=")) for a in specs["sim"])
    assert f"status_file:={tmp_path / 'status.json'}" in specs["runner"]
    assert not any(a.startswith(("initial_pose.", "base_station.", "zone_order"))
                   for a in specs["runner"])
    one = _specs(RunConfig(tree=TREE, params=PARAMS, robots=1), tmp_path / "one")
    assert list(one) == ["sim", "report", "robot1/detect", "robot1/runner"]
