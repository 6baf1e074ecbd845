"""DetectSurvivor against a real DetectSurvivor service in another process, and without one."""

from __future__ import annotations

from collections.abc import Iterator

import pytest
from py_trees.common import Status
from sar_plugins.sar.leaves.detect_survivor import DetectSurvivor
from sar_testing.leaf_harness import (
    NODES,
    ros_seconds,
    spec_zone_manager,
    tick_until_done,
    tree_on,
    wait_for_service,
)
from sar_testing.processes import NodeProcess

from sar_framework.testing import declared_leaf

pytestmark = pytest.mark.ros

LEAF_RUN_S = 60.0
"""Outer safety bound of a leaf's run (well under a second expected, even under load)."""


@pytest.fixture
def detect_server(tmp_path) -> Iterator[NodeProcess]:
    """The echo server: a survivor at (1.5, -2.0) in zone_a, none elsewhere."""
    with NodeProcess([str(NODES / "detect_echo_server.py")], "detect", log_dir=tmp_path) as srv:
        srv.wait_for_output("ready")
        yield srv


def test_missing_service_keeps_running_then_fails_after_its_bound(ros: tuple) -> None:
    node, executor = ros
    leaf = declared_leaf(DetectSurvivor, "DetectSurvivor", zone_manager=spec_zone_manager(),
                          service_name="/no_such_detect", server_timeout_s=1.0)
    tree = tree_on(node, leaf)

    start = ros_seconds()
    for _ in range(5):
        executor.spin_once(timeout_sec=0.02)
        tree.tick()
        assert leaf.status == Status.RUNNING
    assert leaf.feedback_message == "waiting for /no_such_detect"
    assert tick_until_done(executor, tree, LEAF_RUN_S) == Status.FAILURE
    assert ros_seconds() - start >= 1.0  # the leaf's bound counts ROS time
    assert leaf.feedback_message == "/no_such_detect service not available after 1.0 s"
    assert not leaf.was_found()
    assert leaf.survivor_pose() is None


def test_success_with_and_without_a_survivor(ros: tuple, detect_server: NodeProcess) -> None:
    from sar_interfaces.srv import DetectSurvivor as DetectSurvivorSrv
    from sar_plugins.sar.events import SarKind

    from sar_framework.events.emitter import EventEmitter

    node, executor = ros
    zones = spec_zone_manager()
    leaf = declared_leaf(DetectSurvivor, "DetectSurvivor", zone_manager=zones)
    events = EventEmitter(nodes={"0": (leaf, "DetectSurvivor")})
    tree = tree_on(node, leaf, events)
    wait_for_service(node, executor, DetectSurvivorSrv, "/detect_survivor")

    tree.tick()
    assert leaf.status == Status.RUNNING  # the request is out; the answer comes with a spin
    assert tick_until_done(executor, tree, LEAF_RUN_S) == Status.SUCCESS
    assert leaf.was_found()
    assert leaf.survivor_pose() == (1.5, -2.0)
    assert leaf.zone_id() == "zone_a"

    zones.advance()
    assert tick_until_done(executor, tree, LEAF_RUN_S) == Status.SUCCESS
    assert not leaf.was_found()
    assert leaf.survivor_pose() is None
    assert leaf.feedback_message == "zone_b: no survivor"
    detect_server.wait_for_output("asked about zone_b")
    assert detect_server.output.count("asked about") == 2
    told = [(e.kind, e.node_uid, e.value("zone_id"), e.status, e.position) for e in events.emitted]
    assert told == [(SarKind.DETECTION, "0", "zone_a", "FOUND", (1.5, -2.0, 0.0)),
                    (SarKind.DETECTION, "0", "zone_b", "NONE", None)]
