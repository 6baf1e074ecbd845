"""The inspection patrol example, copied and run as a user would: ``sar-tree run``."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

from .test_any_mission import ros_env

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "inspection_patrol"
ROUND = ["shelf A", "shelf B", "shelf C"]
# Outer safety bound of a whole run (about 20 s of wall time on an idle machine).
RUN_BOUND_S = 400


def example_folder(root: Path) -> Path:
    """A copy of the example: the tree, the plugin package and the map."""
    folder = root / "inspection_patrol"
    shutil.copytree(EXAMPLE, folder,
                    ignore=shutil.ignore_patterns("__pycache__", "make_map.py"))
    return folder


def run(folder: Path, *extra: str) -> subprocess.CompletedProcess[str]:
    """``sar-tree run patrol.yaml`` on the warehouse map, from the example's folder."""
    done = subprocess.run([sys.executable, "-m", "sar_framework", "run", "patrol.yaml",
                           "--map", "warehouse.yaml", "--spawn", "0,0,0",
                           "--report-dir", "out", *extra], cwd=folder,
                          capture_output=True, text=True, env=ros_env(folder / "ros_log"),
                          timeout=RUN_BOUND_S, check=False)
    assert done.returncode == 0, done.stdout + done.stderr
    return done
