"""A mission that is not search and rescue, on every surface: ``sar-tree run`` and ``ros2 launch``.

A patrol of the user's own, in a temporary folder that holds nothing but its tree and its
one leaf (a waypoint's pose into the blackboard): Nav2's NavigateToPose, a script and a
failure_is_success around a waypoint inside a wall. It uses no app: no parameter file, no
zones, no detect or report server. Its report says what it did: the goals, where each was
reached or why not, the failures and their reasons.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
from sar_testing.temp_dirs import launch_env

pytestmark = [pytest.mark.slow, pytest.mark.ros]

WAYPOINT = '''\
"""The user's own leaf: a waypoint's pose into the blackboard."""

from typing import Any

import py_trees
from py_trees.common import Status

from sar_framework.engine.param import Param
from sar_framework.engine.plugin import leaf
from sar_framework.engine.ports import OutputPort


@leaf(params=[Param("x", float, description="x (m, map)"),
              Param("y", float, description="y (m, map)")],
      ports=[OutputPort("pose", "geometry_msgs/msg/PoseStamped", description="The pose.")])
class Waypoint(py_trees.behaviour.Behaviour):
    """Write the waypoint (x, y) in the map frame to ``pose``."""

    def __init__(self, name: str, *, x: float, y: float, ports: Any) -> None:
        super().__init__(name=name)
        self.x, self.y, self.ports = x, y, ports

    def update(self) -> Status:
        from geometry_msgs.msg import PoseStamped

        pose = PoseStamped()
        pose.header.frame_id = "map"
        pose.pose.position.x, pose.pose.position.y = self.x, self.y
        pose.pose.orientation.w = 1.0
        self.ports.set("pose", pose)
        return Status.SUCCESS
'''
PATROL = """\
format: 1
name: patrol
description: A shelf, a waypoint inside a wall (skipped), then home.
plugins: [waypoint.py]
blackboard:
  goal: {type: geometry_msgs/msg/PoseStamped, description: the next waypoint}
  laps: {type: int, initial: 0, description: shelves reached}
root:
  sequence:
    name: Patrol
    memory: true
    children:
      - Waypoint: {name: ShelfNW, x: -3.0, y: 3.0, pose: "{goal}"}
      - NavigateToPose: {name: GoShelfNW, goal: "{goal}", server_timeout: 1000}
      - Script: {name: CountShelf, code: "laps += 1"}
      - failure_is_success:
          child:
            sequence:
              name: Blocked
              memory: true
              children:
                - Waypoint: {name: InsideWall, x: 0.0, y: 3.0, pose: "{goal}"}
                - NavigateToPose: {name: GoInsideWall, goal: "{goal}", server_timeout: 1000}
      - Waypoint: {name: Home, x: 0.0, y: 0.0, pose: "{goal}"}
      - NavigateToPose: {name: GoHome, goal: "{goal}", server_timeout: 1000}
"""
ROS2 = Path(sys.prefix) / "bin" / "ros2"
# Outer safety bound of a whole run (about 10 s of wall time on an idle machine).
RUN_BOUND_S = 300


def patrol_folder(root: Path) -> Path:
    """A folder with nothing but the patrol's tree and its leaf."""
    folder = root / "patrol"
    folder.mkdir()
    (folder / "patrol.yaml").write_text(PATROL, encoding="utf-8")
    (folder / "waypoint.py").write_text(WAYPOINT, encoding="utf-8")
    return folder


def ros_env(log_dir: Path) -> dict[str, str]:
    return dict(os.environ, ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST", PYTHONUNBUFFERED="1",
                ROS_LOG_DIR=str(log_dir), RCUTILS_COLORIZED_OUTPUT="0")


@pytest.fixture(scope="module")
def by_sar_tree_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[str, Path]:
    folder = patrol_folder(tmp_path_factory.mktemp("run"))
    done = subprocess.run([sys.executable, "-m", "sar_framework", "run", "patrol.yaml",
                           "--report-dir", "out", "--record", "out/patrol.mcap"], cwd=folder,
                          capture_output=True, text=True, env=ros_env(folder.parent / "ros_log"),
                          timeout=RUN_BOUND_S, check=False)
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout, folder / "out"


@pytest.fixture(scope="module")
def by_ros2_launch(tmp_path_factory: pytest.TempPathFactory) -> tuple[str, Path]:
    if not ROS2.exists():
        pytest.skip("real-stack tier: ros2cli / launch not built")
    folder = patrol_folder(tmp_path_factory.mktemp("launch"))
    out = folder.parent / "out"
    done = subprocess.run([str(ROS2), "launch", "sar_framework", "tree.launch.py",
                           "nav2:=embedded", "tree:=patrol.yaml", f"report_dir:={out}"],
                          cwd=folder, capture_output=True, text=True, stdin=subprocess.DEVNULL,
                          env=launch_env(folder.parent, ros_env(folder.parent / "ros_log")),
                          timeout=RUN_BOUND_S, check=False)
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout + done.stderr, out


def mission(out: Path) -> dict[str, Any]:
    return json.loads((out / "mission.json").read_text(encoding="utf-8"))


def assert_the_report_says_what_the_patrol_did(out: Path) -> None:
    report = mission(out)
    assert report["outcome"] == "SUCCESS" and report["params"] == ""
    told = [(g["node"], g["x"], g["y"], g["result"]) for g in report["goals"]]
    assert told == [("GoShelfNW", -3.0, 3.0, "reached"), ("GoInsideWall", 0.0, 3.0, "failed"),
                    ("GoHome", 0.0, 0.0, "reached")]
    assert "inside an obstacle" in report["goals"][1]["reason"]
    failed = {(f["what"], f["name"]) for f in report["failures"]}
    assert failed == {("failure", "GoInsideWall"), ("skip", "FailureIsSuccess")}
    assert all("error code 206" in f["message"] for f in report["failures"])
    # One clock: each goal is sent after the previous one ended, failures when theirs failed.
    goals = report["goals"]
    assert 0 <= goals[0]["sent_sim_s"] < goals[0]["ended_sim_s"] <= goals[1]["sent_sim_s"]
    assert goals[1]["ended_sim_s"] == report["failures"][0]["sim_s"]
    assert goals[2]["ended_sim_s"] <= report["sim_duration_s"]
    final = report["final_position"]
    assert abs(final["x"]) < 0.3 and abs(final["y"]) < 0.3
    assert not any(key.startswith(("zone", "survivor", "base")) or key == "at_base"
                   for key in report)
    assert report["entries"]["laps"]["value"] == "1"  # the script ran once
    assert (out / "mission.png").stat().st_size > 0 and (out / "tree.svg").stat().st_size > 0


def test_sar_tree_run_runs_a_tree_without_an_app_from_its_own_folder(by_sar_tree_run) -> None:
    printed, out = by_sar_tree_run
    assert "patrol.yaml; embedded simulator" in printed  # no parameter file named
    assert "goal (-3.00, 3.00) reached" in printed
    assert ("goals reached: 2 of 3; goals not reached: GoInsideWall (0.00, 3.00); "
            "final position (") in printed
    assert "zone" not in printed and "survivor" not in printed
    assert not (out / "detect.log").exists() and not (out / "report.log").exists()
    assert_the_report_says_what_the_patrol_did(out)
    # Nothing but the report folder is written beside the tree (Python's own bytecode cache
    # of the imported leaf module aside, written where bytecode writing is on).
    written = sorted(p.name for p in out.parent.iterdir() if p.name != "__pycache__")
    assert written == ["out", "patrol.yaml", "waypoint.py"]


def test_its_recording_replays_to_the_same_report(by_sar_tree_run, tmp_path: Path) -> None:
    out = by_sar_tree_run[1]
    done = subprocess.run([sys.executable, "-m", "sar_framework", "replay",
                           str(out / "patrol.mcap"), "--report-dir", str(tmp_path / "again")],
                          capture_output=True, text=True, timeout=RUN_BOUND_S, check=False)
    assert done.returncode == 0, done.stdout + done.stderr
    replayed, ran = mission(tmp_path / "again"), mission(out)
    assert replayed["goals"] == ran["goals"] and replayed["failures"] == ran["failures"]


def test_ros2_launch_writes_the_same_report(by_ros2_launch, by_sar_tree_run) -> None:
    printed, out = by_ros2_launch
    assert "sar-detect-survivor-server" not in printed
    assert "sar-report-survivor-server" not in printed
    assert_the_report_says_what_the_patrol_did(out)
    launched, ran = mission(out), mission(by_sar_tree_run[1])
    assert set(launched) == set(ran)
    assert [(g["node"], g["result"]) for g in launched["goals"]] == \
        [(g["node"], g["result"]) for g in ran["goals"]]
