"""Run only by test_ros_environment.py, under ``pytest -n 2``: each test notes its domain.

Not a ``test_*.py`` file, so the normal run does not collect it.
"""

from __future__ import annotations

import os
import time
from pathlib import Path

import pytest


@pytest.mark.parametrize("index", [0, 1, 2, 3])
def test_note_the_domain(index: int) -> None:
    time.sleep(0.5)  # long enough that both workers take tests
    worker = os.environ.get("PYTEST_XDIST_WORKER", "none")
    folder = Path(os.environ["SAR_XDIST_PROBE_DIR"])
    (folder / f"{index}.txt").write_text(f"{worker} {os.environ['ROS_DOMAIN_ID']}")
