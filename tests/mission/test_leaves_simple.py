"""The leaves without a ROS client: conditions never RUNNING, AdvanceZone, LogNoDetection."""

from __future__ import annotations

import pytest
from py_trees.common import Status
from sar_plugins.sar.leaves.advance_zone import AdvanceZone
from sar_plugins.sar.leaves.is_survivor_detected import IsSurvivorDetected
from sar_plugins.sar.leaves.log_no_detection import LogNoDetection
from sar_plugins.sar.leaves.zones_remaining import ZonesRemaining
from sar_testing.leaf_harness import FixedDetector, spec_zone_manager

from sar_framework.testing import declared_leaf


def test_zones_remaining_follows_the_zone_manager() -> None:
    zones = spec_zone_manager()
    leaf = ZonesRemaining("ZonesRemaining?", zone_manager=zones)
    for _ in range(zones.total_zones()):
        leaf.tick_once()
        assert leaf.status == Status.SUCCESS
        zones.advance()
    leaf.tick_once()
    assert leaf.status == Status.FAILURE
    assert leaf.feedback_message == "all 4 zones visited"


def test_is_survivor_detected_reads_the_detector() -> None:
    detector = FixedDetector()
    leaf = IsSurvivorDetected("IsSurvivorDetected?", detector=detector)
    leaf.tick_once()
    assert leaf.status == Status.FAILURE
    detector.pose = (-2.5, 3.2)
    leaf.tick_once()
    assert leaf.status == Status.SUCCESS
    assert leaf.feedback_message == "survivor at (-2.50, 3.20)"


def test_advance_zone_always_succeeds() -> None:
    zones = spec_zone_manager()
    leaf = AdvanceZone("AdvanceZone", zone_manager=zones)
    for expected in (1, 2, 3, 4, 4):
        leaf.tick_once()
        assert leaf.status == Status.SUCCESS
        assert zones.current_index() == expected


def test_log_no_detection_without_a_node_uses_the_py_trees_logger() -> None:
    zones = spec_zone_manager()
    zones.advance()
    leaf = LogNoDetection("LogNoDetection", zone_manager=zones)
    leaf.setup()
    leaf.tick_once()
    assert leaf.status == Status.SUCCESS
    assert leaf.feedback_message == "No survivor found at zone_b."


@pytest.mark.ros
def test_log_no_detection_logs_the_spec_line_on_the_node(ros: tuple,
                                                         capfd: pytest.CaptureFixture) -> None:
    node, _executor = ros
    zones = spec_zone_manager()
    zones.advance()
    leaf = LogNoDetection("LogNoDetection", zone_manager=zones)
    leaf.setup(node=node)
    leaf.tick_once()
    assert leaf.status == Status.SUCCESS
    assert "[sar_test]: No survivor found at zone_b." in capfd.readouterr().err
    while zones.has_remaining():
        zones.advance()
    leaf.tick_once()
    assert leaf.status == Status.FAILURE


def test_dwell_with_jitter_waits_a_fresh_random_extra_at_each_start() -> None:
    import random
    import re
    import time

    from sar_plugins.dwell import Dwell

    def drawn_wait(leaf: Dwell) -> float:
        leaf.initialise()
        assert leaf.update() == Status.RUNNING
        return float(re.fullmatch(r"waiting: \S+ s of (\S+) s left", leaf.feedback_message)[1])

    leaf = declared_leaf(Dwell, "GiveWay", duration=1.0, jitter=8.0, rng=random.Random(7))
    waits = [drawn_wait(leaf) for _ in range(20)]
    assert all(1.0 <= w <= 9.0 for w in waits)
    assert len(set(waits)) >= 15  # drawn anew each time (one decimal shown)
    assert max(waits) - min(waits) > 4.0  # spread over the range, not stuck at one end
    assert drawn_wait(declared_leaf(Dwell, "Fixed", duration=2.0)) == 2.0  # no jitter: the duration
    short = declared_leaf(Dwell, "Short", duration=0.0, jitter=0.05)
    short.initialise()
    time.sleep(0.06)
    assert short.update() == Status.SUCCESS
