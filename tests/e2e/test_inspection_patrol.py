"""The inspection patrol example, end to end: ``sar-tree run``, ``ros2 launch`` and replay.

The example's own folder is copied to a temporary one (its tree, its plugin package and its
map, nothing else) and run there on its warehouse map. The report speaks of the app's own
things: the shelves scanned and the waypoints visited, and so does the report a replay of its
recording draws (the recording keeps the app's plugin files). The app's scan server is a
program of its own, started beside the runner. ``--set battery=`` changes the battery the
tree starts with, and a low one sends the robot home after one round.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
from sar_testing.temp_dirs import launch_env

from .patrol_example import ROUND, RUN_BOUND_S, example_folder, run
from .test_any_mission import ROS2, ros_env

pytestmark = [pytest.mark.slow, pytest.mark.ros]


def mission(out: Path) -> dict[str, Any]:
    return json.loads((out / "mission.json").read_text(encoding="utf-8"))


def test_the_patrol_scans_every_shelf_twice_and_says_so(tmp_path: Path) -> None:
    folder = example_folder(tmp_path)
    done = run(folder, "--set", "battery=100", "--record", "out/patrol.mcap")
    assert "shelves scanned: 6 (A, B, C, A, B, C); waypoints visited: 7" in done.stdout
    assert done.stdout.count("runner | shelf B scanned") == 2  # the scan server's answer
    scan_log = (folder / "out" / "scan.log").read_text(encoding="utf-8")
    assert "scanning shelves A, B, C" in scan_log  # its own process, not the runner's
    report = mission(folder / "out")
    assert report["outcome"] == "SUCCESS", report
    assert [s["shelf"] for s in report["shelves_scanned"]] == ["A", "B", "C"] * 2
    assert report["waypoints_visited"] == ROUND * 2 + ["GoHome"]
    times = [s["sim_s"] for s in report["shelves_scanned"]]
    assert times == sorted(times) and times[0] > 0
    final = report["final_position"]
    assert abs(final["x"]) < 0.3 and abs(final["y"]) < 0.3
    replayed = subprocess.run([sys.executable, "-m", "sar_framework", "replay",
                               "out/patrol.mcap", "--report-dir", "replayed"], cwd=folder,
                              capture_output=True, text=True, env=ros_env(folder / "ros_log"),
                              timeout=RUN_BOUND_S, check=False)
    assert replayed.returncode == 0, replayed.stdout + replayed.stderr
    assert "warning" not in replayed.stderr, replayed.stderr
    again = mission(folder / "replayed")
    assert [(g["node"], g["result"]) for g in again["goals"]] == \
        [(g["node"], g["result"]) for g in report["goals"]]
    # the app came back from the recorded plugin files: its keys are in the replayed report
    assert again["shelves_scanned"] == report["shelves_scanned"]
    assert again["waypoints_visited"] == report["waypoints_visited"]


def test_a_low_battery_set_from_the_command_line_sends_it_home_after_one_round(
        tmp_path: Path) -> None:
    folder = example_folder(tmp_path)
    run(folder, "--set", "battery=30")  # 30 - 3 x 5 = 15: not above 20 for a second round
    report = mission(folder / "out")
    assert report["outcome"] == "SUCCESS", report
    assert [s["shelf"] for s in report["shelves_scanned"]] == ["A", "B", "C"]
    assert report["waypoints_visited"] == [*ROUND, "GoHome"]


def test_ros2_launch_runs_the_patrol_and_writes_its_report(tmp_path: Path) -> None:
    if not ROS2.exists():
        pytest.skip("real-stack tier: ros2cli / launch not built")
    folder = example_folder(tmp_path)
    out = tmp_path / "out"
    done = subprocess.run([str(ROS2), "launch", "sar_framework", "tree.launch.py",
                           "nav2:=embedded", "tree:=patrol.yaml", "map:=warehouse.yaml",
                           "spawn:=0,0,0", "set:=battery=30", f"report_dir:={out}"],
                          cwd=folder, capture_output=True, text=True, stdin=subprocess.DEVNULL,
                          env=launch_env(tmp_path, ros_env(tmp_path / "ros_log")),
                          timeout=RUN_BOUND_S, check=False)
    assert done.returncode == 0, done.stdout + done.stderr
    report = mission(out)
    assert report["outcome"] == "SUCCESS", report
    # the launch's set:= reaches the tree as --set does: one round on a low battery (half
    # the mission of two rounds)
    assert [s["shelf"] for s in report["shelves_scanned"]] == ["A", "B", "C"]
    assert report["waypoints_visited"] == [*ROUND, "GoHome"]
