"""Soak (``-m soak`` only): the launch Ctrl-C scenario 20 times while both cores are loaded.

Runs ``benchmarks/soak_launch_ctrl_c.py`` (its table is in the output); every run must be
clean. About 20 x 15-40 s: never part of the default run.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from sar_testing.launch_ctrl_c import ROS2

REPO = Path(__file__).resolve().parents[2]
pytestmark = [
    pytest.mark.soak, pytest.mark.ros, pytest.mark.slow,
    pytest.mark.skipif(not ROS2.exists(), reason="real-stack tier: ros2cli / launch not built"),
    pytest.mark.timeout(3600),
]


def test_ctrl_c_under_ros2_launch_is_clean_20_times_under_load() -> None:
    soak = subprocess.run([sys.executable, str(REPO / "benchmarks" / "soak_launch_ctrl_c.py"),
                           "--runs", "20"], stdin=subprocess.DEVNULL, capture_output=True,
                          text=True, timeout=3500, check=False)
    print(soak.stdout)
    assert soak.returncode == 0, soak.stdout + soak.stderr
    assert "\nclean     20\n" in soak.stdout, soak.stdout
