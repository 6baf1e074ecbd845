"""Soak (``-m soak`` only): seven servers stopped in the same instant, 60 rounds, under load.

Runs ``benchmarks/soak_server_teardown.py`` (its table is in the output); every server of
every round must exit 0. Fast DDS's participant teardown can hang here; the bound of
``sar_framework/ros/teardown.py`` ends such a process with 0. About 60 x 5-15 s: never part
of the default run.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
pytestmark = [pytest.mark.soak, pytest.mark.ros, pytest.mark.slow, pytest.mark.timeout(3600)]


def test_seven_servers_stopped_together_all_exit_0_sixty_times_under_load() -> None:
    soak = subprocess.run([sys.executable, str(REPO / "benchmarks" / "soak_server_teardown.py"),
                           "--rounds", "60"], stdin=subprocess.DEVNULL, capture_output=True,
                          text=True, timeout=3500, check=False)  # outer safety bound
    print(soak.stdout)
    assert soak.returncode == 0, soak.stdout + soak.stderr
    assert "\n| 60 | 60 | 0 | " in soak.stdout, soak.stdout
