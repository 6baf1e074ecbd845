"""``sar-tree run`` checks its inputs with no ROS importable, up to starting its children.

Regression: ``run/inputs.py`` (now ``orchestrate/inputs.py``) imported the simulator node
(rclpy, every Nav2 stand-in server,
``nav2_msgs``) only to read its parameter table, so in a half-built environment the run
raised ``ModuleNotFoundError: nav2_msgs`` before anything was checked.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from .helpers import DEFAULT_TREE, REPO

# Runs sar-tree in a process where rclpy and nav2_msgs cannot be imported; a good input
# reaches the first child's start, where the process reports the ROS modules loaded so far.
DRIVER = """
import os, sys

BLOCKED = ("rclpy", "nav2_msgs")
ROS = ("rclpy", "rcl_interfaces", "nav2_msgs", "nav_msgs", "geometry_msgs", "tf2_msgs",
       "tf2_ros", "sar_interfaces", "sar_fleet_interfaces", "action_msgs", "rosgraph_msgs",
       "launch", "launch_ros")


class Blocker:
    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] in BLOCKED:
            raise ModuleNotFoundError(f"No module named {name!r}")
        return None


sys.meta_path.insert(0, Blocker())

import sar_framework.orchestrate.orchestrator as mission


def starting(spec, *args, **kwargs):
    loaded = sorted(m for m in sys.modules if m.split(".")[0] in ROS)
    print(f"starting {spec.label}; ROS modules loaded: {loaded}", flush=True)
    os._exit(17)


mission.start_child = starting
from sar_framework.cli import main

sys.exit(main(sys.argv[1:]))
"""

THREE_MISTAKES = """\
/**:
  ros__parameters:
    zone_order: ["zone_a"]
    zones:
      zone_a: {x: -3.0, y: abc, yaw: 0.0}
    tick_rate_hz: -2.0
"""


def _run(tmp_path: Path, *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-c", DRIVER, "run", *args,
                           "--report-dir", str(tmp_path / "r")],
                          capture_output=True, text=True, timeout=60, cwd=REPO, check=False)


def test_the_blocker_blocks(tmp_path: Path) -> None:
    script = DRIVER.split("import sar_framework", maxsplit=1)[0] + "import nav2_msgs\n"
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                            timeout=60, check=False)
    assert "ModuleNotFoundError: No module named 'nav2_msgs'" in result.stderr


def test_bad_inputs_are_reported_without_ros(tmp_path: Path) -> None:
    params = tmp_path / "params.yaml"
    params.write_text(THREE_MISTAKES)
    tree = tmp_path / "bad.yaml"
    tree.write_text("format: 1\nroot:\n  sequence:\n    children:\n      - NavigateToZonee: {}\n")
    result = _run(tmp_path, str(tree), "--params", str(params), "--speed", "0",
                  "--sim-param", "speed_scale:=fast", "--detect-param", "answer_delay_wall_s:=-1")
    assert result.returncode == 2, result.stdout + result.stderr
    assert result.stdout == ""
    for line in (f"{tree}:5:9: error:",
                 f"{params}:5:25: zones.zone_a.y: must be a number, got 'abc'",
                 f"{params}:6:5: tick_rate_hz: must be > 0, got -2.0",
                 "--speed must be > 0 and <= 1000, got 0.0",
                 "--sim-param: speed_scale: must be a number, got 'fast'",
                 "--detect-param: answer_delay_wall_s: must be >= 0, got -1"):
        assert line in result.stderr, result.stderr
    assert "Traceback" not in result.stderr and "ModuleNotFoundError" not in result.stderr
    assert not (tmp_path / "r").exists()


def test_a_good_input_gets_as_far_as_starting_the_children(tmp_path: Path) -> None:
    result = _run(tmp_path, str(DEFAULT_TREE), "--sim-param", "blocked_areas:=['zone_b']")
    assert result.returncode == 17, result.stdout + result.stderr
    assert "starting sim; ROS modules loaded: []" in result.stdout
