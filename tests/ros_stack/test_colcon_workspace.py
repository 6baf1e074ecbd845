"""The repository as a package of a colcon workspace, resolved by ros2 from the install space.

Real-stack tier (colcon and ros2cli in the venv). The workspace links to this repository,
as ``git clone`` into ``src/`` would give; sar_interfaces comes from the venv underlay.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

BIN = Path(sys.prefix) / "bin"
REPO = Path(__file__).resolve().parents[2]
pytestmark = [
    pytest.mark.ros, pytest.mark.slow,
    pytest.mark.skipif(not (BIN / "ros2").exists() or not (BIN / "colcon").exists(),
                       reason="real-stack tier: colcon / ros2cli not in the venv (make setup "
                       "with ../shared/ros-overlay or SAR_ROS_OVERLAY_SRC)"),
]


def test_colcon_build_installs_a_package_ros2_launch_and_run_resolve(tmp_path):
    print("tier: real ROS 2 stack (colcon + ros2 from .venv)")
    (tmp_path / "src").mkdir()
    (tmp_path / "src" / "sar_framework").symlink_to(REPO)
    env = dict(os.environ, COLCON_HOME=str(tmp_path / "colcon-home"))
    env["PATH"] = f"{BIN}{os.pathsep}{env.get('PATH', '')}"
    build = subprocess.run(
        [str(BIN / "colcon"), "--log-base", str(tmp_path / "log"), "build",
         "--base-paths", str(tmp_path / "src"), "--build-base", str(tmp_path / "build"),
         "--install-base", str(tmp_path / "install"), "--packages-select", "sar_framework"],
        cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300, check=False)
    assert build.returncode == 0, build.stdout + build.stderr
    install = tmp_path / "install" / "sar_framework"
    share = install / "share" / "sar_framework"
    for path in ("launch/search_and_rescue.launch.py", "launch/tree.launch.py",
                 "config/nav2_params.yaml",
                 "maps/final_project_map.yaml", "trees/search_and_rescue.yaml", "package.xml"):
        assert (share / path).is_file(), path
    assert (install / "lib" / "sar_framework" / "sar-mission-runner").is_file()

    # What `source install/setup.bash` does for ament: the install space over the venv.
    env["AMENT_PREFIX_PATH"] = os.pathsep.join([str(install), sys.prefix])

    def ros2(*args: str) -> str:
        done = subprocess.run([str(BIN / "ros2"), *args], env=env, capture_output=True,
                              text=True, timeout=120, check=False)
        assert done.returncode == 0, done.stdout + done.stderr
        return done.stdout

    assert ros2("pkg", "prefix", "sar_framework").strip() == str(install)
    assert "sar_framework sar-mission-runner" in ros2("pkg", "executables", "sar_framework")
    # The app's launch file shows its own arguments and those of tree.launch.py it includes.
    shown = ros2("launch", "sar_framework", "search_and_rescue.launch.py", "--show-args")
    assert "'survivors_file':" in shown and "'nav2':" in shown and "'tree':" in shown, shown
    printed = ros2("launch", "--print", "sar_framework", "search_and_rescue.launch.py",
                   "nav2:=embedded")
    assert "LaunchDescription" in printed and "IncludeLaunchDescription" in printed, printed
    printed = ros2("launch", "--print", "sar_framework", "tree.launch.py", "nav2:=embedded")
    assert "LaunchDescription" in printed and "OpaqueFunction" in printed, printed
