"""``sar-tree run --set`` and the launch argument ``set:=`` give a declared entry its
initial value: the report's final value shows the tree started from it."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from sar_testing.temp_dirs import launch_env

from .test_any_mission import ROS2, RUN_BOUND_S, ros_env

pytestmark = pytest.mark.ros

DRAIN = """\
format: 1
name: drain
blackboard:
  battery: {type: float, initial: 60.0, description: charge in percent}
  label: {type: str, initial: none}
root:
  Script: {code: "battery := battery - 1"}
"""


def entries(out: Path) -> dict[str, str]:
    report = json.loads((out / "mission.json").read_text(encoding="utf-8"))
    assert report["outcome"] == "SUCCESS", report
    return {name: entry["value"] for name, entry in report["entries"].items()}


def test_sar_tree_run_sets_initial_values(tmp_path: Path) -> None:
    (tmp_path / "drain.yaml").write_text(DRAIN, encoding="utf-8")
    done = subprocess.run([sys.executable, "-m", "sar_framework", "run", "drain.yaml",
                           "--set", "battery=50", "--set", "label=two words",
                           "--report-dir", "out"], cwd=tmp_path, capture_output=True,
                          text=True, env=ros_env(tmp_path / "ros_log"), timeout=RUN_BOUND_S,
                          check=False)
    assert done.returncode == 0, done.stdout + done.stderr
    assert entries(tmp_path / "out") == {"battery": "49", "label": "'two words'"}


def test_ros2_launch_sets_initial_values(tmp_path: Path) -> None:
    if not ROS2.exists():
        pytest.skip("real-stack tier: ros2cli / launch not built")
    (tmp_path / "drain.yaml").write_text(DRAIN, encoding="utf-8")
    out = tmp_path / "out"
    done = subprocess.run([str(ROS2), "launch", "sar_framework", "search_and_rescue.launch.py",
                           "nav2:=embedded", "tree:=drain.yaml", "set:=battery=50 label='a b'",
                           f"report_dir:={out}"], cwd=tmp_path, capture_output=True, text=True,
                          stdin=subprocess.DEVNULL,
                          env=launch_env(tmp_path, ros_env(tmp_path / "ros_log")),
                          timeout=RUN_BOUND_S, check=False)
    assert done.returncode == 0, done.stdout + done.stderr
    assert entries(out) == {"battery": "49", "label": "'a b'"}
