"""Every Nav2 leaf has the ports of Nav2's palette (nav2_tree_nodes.xml, read from the overlay).

Name, direction, type (the palette's C++ type in our spelling) and default; a palette port
without a default is one the tree may leave unbound (never a required port here).
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest
import sar_plugins.nav2 as nav2

from sar_framework.engine.plugin import PLUGIN_ATTRIBUTE, PluginSpec
from sar_framework.engine.ports import NO_DEFAULT
from sar_framework.interop.btcpp_file import read_palette
from sar_framework.interop.btcpp_models import literal_default

OVERLAY = Path("/work/shared/ros-overlay/src")
#: Nav2's leaves (its controls and decorators are node kinds, tests/interop/test_palette.py).
REQUIRED = {
    "ComputePathToPose", "ComputePathThroughPoses", "FollowPath", "Spin", "BackUp",
    "DriveOnHeading", "Wait", "ClearEntireCostmap", "ClearCostmapAroundRobot",
    "ClearCostmapExceptRegion", "SmoothPath", "ControllerSelector", "PlannerSelector",
    "RemovePassedGoals", "TruncatePath", "CancelControl", "NavigateToPose",
    "NavigateThroughPoses", "GoalUpdated", "GlobalUpdatedGoal", "IsPathValid", "IsStuck",
    "GoalReached", "TimeExpired", "PathExpiringTimer", "WouldAControllerRecoveryHelp",
    "WouldAPlannerRecoveryHelp",
}


def palette_path() -> Path:
    for prefix in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep):
        found = Path(prefix) / "share" / "nav2_behavior_tree" / "nav2_tree_nodes.xml"
        if prefix and found.exists():
            return found
    return OVERLAY / "nav2_behavior_tree" / "nav2_tree_nodes.xml"


PALETTE, PROBLEMS = read_palette(str(palette_path()))
LEAVES: dict[str, PluginSpec] = {
    getattr(nav2, name).__dict__[PLUGIN_ATTRIBUTE].name:
        getattr(nav2, name).__dict__[PLUGIN_ATTRIBUTE] for name in nav2.__all__
    if PLUGIN_ATTRIBUTE in getattr(nav2, name).__dict__  # the controls and decorators are kinds
}


def test_the_palette_is_read_and_every_required_leaf_exists() -> None:
    assert not PROBLEMS
    assert set(LEAVES) >= REQUIRED, sorted(REQUIRED - set(LEAVES))
    for name in LEAVES:
        assert PALETTE[name].is_leaf, name


@pytest.mark.parametrize("name", sorted(LEAVES))
def test_leaf_ports_are_the_palettes(name: str) -> None:
    spec, model = LEAVES[name], PALETTE[name]
    ours = {p.name: p for p in spec.ports}
    theirs = {p.name: p for p in model.ports}
    assert set(ours) == set(theirs), (sorted(set(ours) ^ set(theirs)))
    assert not spec.params  # Nav2's nodes have ports only
    for port_name, model_port in theirs.items():
        port = ours[port_name]
        where = f"{name}.{port_name}"
        assert port.direction.value == model_port.direction, where
        assert port.type == model_port.type, (where, port.type, model_port.cpp)
        expected = literal_default(model_port)
        got = None if port.default is NO_DEFAULT else port.default
        assert got == expected, (where, got, expected)
        if expected is None:
            assert not port.required, f"{where}: the palette has no default; optional here"
        assert port.description, where


def test_a_changed_palette_port_would_be_noticed() -> None:
    """The comparison can fail: Spin's spin_dist with another default is caught."""
    import dataclasses

    spec = LEAVES["Spin"]
    wrong = tuple(dataclasses.replace(p, default=3.0) if p.name == "spin_dist" else p
                  for p in spec.ports)
    LEAVES["Spin"] = dataclasses.replace(spec, ports=wrong)
    try:
        with pytest.raises(AssertionError, match="spin_dist"):
            test_leaf_ports_are_the_palettes("Spin")
    finally:
        LEAVES["Spin"] = spec
