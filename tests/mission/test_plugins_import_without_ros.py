"""Built-in plugin modules and the search-and-rescue app's leaf modules import no ROS, and
each plugin's declaration matches its class."""

from __future__ import annotations

import pkgutil
import subprocess
import sys

import pytest
import sar_plugins
import sar_plugins.sar.leaves

from sar_framework.engine.plugin import PLUGIN_ATTRIBUTE, constructor_problems
from sar_framework.engine.registry import BUILTIN_PACKAGE, Registry

SAR_LEAVES = "sar_plugins.sar.leaves"
MODULES = sorted([*(f"sar_plugins.{info.name}" for info in
                    pkgutil.iter_modules(sar_plugins.__path__)),
                  *(f"{SAR_LEAVES}.{info.name}" for info in
                    pkgutil.iter_modules(sar_plugins.sar.leaves.__path__))])
MISSION_LEAVES = {
    "ZonesRemaining", "IsSurvivorDetected", "NavigateToZone", "NavigateToBase",
    "DetectSurvivor", "BroadcastSurvivorTF", "NotifyBase", "AdvanceZone", "LogNoDetection",
}


def builtin_registry() -> Registry:
    """The built-in leaves and the search-and-rescue app's."""
    registry = Registry()
    assert registry.import_module(BUILTIN_PACKAGE), registry.diagnostics
    assert registry.import_module(SAR_LEAVES), registry.diagnostics
    assert not registry.diagnostics
    return registry


@pytest.mark.parametrize("module", MODULES)
def test_importing_a_plugin_module_does_not_import_rclpy(module: str) -> None:
    code = (f"import sys, {module}\n"
            "ros = sorted(m for m in sys.modules if m.split('.')[0] in "
            "{'rclpy', 'rosidl_runtime_py', 'nav2_msgs', 'sar_interfaces',"
            " 'sar_fleet_interfaces', 'geometry_msgs'})\n"
            "assert not ros, ros")
    done = subprocess.run([sys.executable, "-c", code], check=False, capture_output=True,
                          text=True, timeout=60)
    assert done.returncode == 0, done.stderr


def test_all_nine_mission_leaves_are_the_apps() -> None:
    assert set(builtin_registry().names()) >= MISSION_LEAVES
    core = Registry()
    assert core.import_module(BUILTIN_PACKAGE)
    assert not set(core.names()) & MISSION_LEAVES


@pytest.mark.parametrize("name", sorted(MISSION_LEAVES))
def test_a_mission_leaf_is_documented(name: str) -> None:
    spec = builtin_registry().get(name)
    assert spec is not None
    assert PLUGIN_ATTRIBUTE in spec.cls.__dict__
    assert spec.description and not spec.description.startswith("Args")
    for param in spec.params:
        assert param.description, f"{name}.{param.name} has no description"


def test_no_built_in_leaf_repeats_a_default_or_misses_a_declared_name() -> None:
    registry = builtin_registry()  # asserts no diagnostics, warnings included
    problems = [f"{spec.name}: {problem}" for spec in registry
                for problem in constructor_problems(spec)]
    assert not problems, "\n".join(problems)
