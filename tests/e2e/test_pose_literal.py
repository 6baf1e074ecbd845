"""A goal written in the tree file as a pose literal drives the robot there.

``sar-tree run`` in the embedded simulator, a tree of Nav2's NavigateToPose only: one goal
in BT.CPP's text form (``x;y;yaw``), then one as the pose shorthand ``{x, y, yaw}``. No
leaf of the user's own writes a pose to the blackboard; the report says where each goal
was and that it was reached, and the robot ends at the last one.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = [pytest.mark.slow, pytest.mark.ros]

TREE = """\
format: 1
name: go_there
root:
  sequence:
    memory: true
    children:
      - NavigateToPose: {name: GoShelf, goal: "-3.0;3.0;0.0", server_timeout: 1000}
      - NavigateToPose: {name: GoThere, goal: {x: 1.0, y: 2.0, yaw: 0.0}, server_timeout: 1000}
"""
# Outer safety bound of the whole run (about 10 s of wall time on an idle machine).
RUN_BOUND_S = 300


def test_a_pose_literal_drives_the_robot_there(tmp_path: Path) -> None:
    (tmp_path / "go_there.yaml").write_text(TREE, encoding="utf-8")
    env = dict(os.environ, ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST", PYTHONUNBUFFERED="1",
               ROS_LOG_DIR=str(tmp_path / "ros_log"), RCUTILS_COLORIZED_OUTPUT="0")
    done = subprocess.run([sys.executable, "-m", "sar_framework", "run", "go_there.yaml",
                           "--report-dir", "out"], cwd=tmp_path, capture_output=True, text=True,
                          env=env, timeout=RUN_BOUND_S, check=False)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "goal (1.00, 2.00) reached" in done.stdout, done.stdout
    report = json.loads((tmp_path / "out" / "mission.json").read_text(encoding="utf-8"))
    assert report["outcome"] == "SUCCESS"
    assert [(g["node"], g["x"], g["y"], g["result"]) for g in report["goals"]] == [
        ("GoShelf", -3.0, 3.0, "reached"), ("GoThere", 1.0, 2.0, "reached")]
    final = report["final_position"]
    assert abs(final["x"] - 1.0) < 0.3 and abs(final["y"] - 2.0) < 0.3, final
