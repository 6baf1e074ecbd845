"""The engine, the validate path and the built-in plugin modules never import ROS."""

from __future__ import annotations

import subprocess
import sys

from .conftest import FIXTURES, REPO

SCRIPT = f"""
import importlib, pkgutil, sys
import sar_framework.engine as engine
for info in pkgutil.walk_packages(engine.__path__, "sar_framework.engine."):
    importlib.import_module(info.name)
from sar_framework import cli
code = cli.main(["validate", "-q", {str(FIXTURES / "search_and_rescue.yaml")!r}])
assert code == 0, code
import sar_plugins
for info in pkgutil.iter_modules(sar_plugins.__path__):
    importlib.import_module("sar_plugins." + info.name)
ros = sorted(m for m in sys.modules if m.split(".")[0] in
             ("rclpy", "rcl_interfaces", "geometry_msgs", "nav2_msgs", "tf2_ros", "sar_interfaces",
              "sar_fleet_interfaces"))
print(ros)
"""


def test_engine_and_validate_do_not_import_ros() -> None:
    run = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True,
                         cwd=REPO, check=False, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "[]"
