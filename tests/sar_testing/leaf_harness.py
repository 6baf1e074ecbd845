"""Helpers for the mission leaf tests: the spec's zones and a ZoneManager on them.

The generic ROS helpers (trees set up on a node, ticking with spinning, probes) live in
:mod:`sar_framework.testing.ros_harness`; they are re-exported here for the tests that
import them from this module.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from sar_plugins.sar.zone_manager import ZoneManager

from sar_framework.testing.ros_harness import (
    DISCOVERY_S,
    TERMINAL,
    OutputMark,
    TfStaticRecorder,
    TreeMaker,
    tick_until_done,
    tree_on,
    wait_for_action_server,
    wait_for_service,
)

__all__ = ["BASE", "DISCOVERY_S", "NODES", "SPEC_ZONES", "TERMINAL", "OutputMark",
           "TfStaticRecorder", "TreeMaker", "ros_seconds", "spec_zone_manager",
           "tick_until_done", "tree_on",
           "wait_for_action_server", "wait_for_service"]

NODES = Path(__file__).resolve().parent / "nodes"
SPEC_ZONES = [
    {"id": "zone_a", "x": -3.0, "y": 3.0, "yaw": 0.0},
    {"id": "zone_b", "x": 3.5, "y": 3.0, "yaw": 1.57},
    {"id": "zone_c", "x": 4.0, "y": -3.0, "yaw": 3.14},
    {"id": "zone_d", "x": -3.5, "y": -3.0, "yaw": -1.57},
]
BASE = {"x": 0.0, "y": 0.0, "yaw": 0.0}


def spec_zone_manager(zones: list[dict[str, Any]] | None = None) -> ZoneManager:
    """A ZoneManager with the spec's zones (or ``zones``) and base station."""
    return ZoneManager(SPEC_ZONES if zones is None else zones, BASE)


@dataclass
class FixedDetector:
    """Stands in for DetectSurvivor: a settable detection result."""

    pose: tuple[float, float] | None = None

    def was_found(self) -> bool:
        return self.pose is not None

    def survivor_pose(self) -> tuple[float, float] | None:
        return self.pose


def ros_seconds() -> float:
    """The ROS clock the leaves count their bounds on, in seconds (no ``/clock`` here)."""
    from rclpy.clock import Clock, ClockType

    return Clock(clock_type=ClockType.ROS_TIME).now().nanoseconds / 1e9
