"""The seed tree loaded from YAML with the real plugins: its wiring, then a whole mission.

The mission runs against the fake servers (a scripted NavigateToPose server that succeeds,
the detect echo server with one survivor in zone_a at (1.5, -2.0), a report server that
answers after 0.2 s), ticked the way the runner ticks.
"""

from __future__ import annotations

import re
from collections.abc import Iterator

import py_trees
import pytest
from py_trees.common import Status
from sar_plugins.sar.leaves.broadcast_survivor_tf import BroadcastSurvivorTF
from sar_plugins.sar.leaves.detect_survivor import DetectSurvivor
from sar_plugins.sar.leaves.is_survivor_detected import IsSurvivorDetected
from sar_plugins.sar.leaves.navigate_to_base import NavigateToBase
from sar_plugins.sar.leaves.notify_base import NotifyBase
from sar_plugins.sar.zone_manager import ZoneManager
from sar_testing.leaf_harness import (
    NODES,
    TfStaticRecorder,
    spec_zone_manager,
    tree_on,
    wait_for_action_server,
    wait_for_service,
)
from sar_testing.processes import NodeProcess
from sar_testing.spin import spin_until

from sar_framework import load_tree


def load_seed(repo_root, zones: ZoneManager) -> py_trees.behaviour.Behaviour:
    return load_tree(repo_root / "trees" / "search_and_rescue.yaml",
                     context={"zone_manager": zones}).root


def leaves_of(root: py_trees.behaviour.Behaviour, cls: type) -> list:
    return [b for b in root.iterate() if isinstance(b, cls)]


def test_seed_tree_wires_the_leaves_by_reference(repo_root) -> None:
    zones = spec_zone_manager()
    root = load_seed(repo_root, zones)

    (detect,) = leaves_of(root, DetectSurvivor)
    (found,) = leaves_of(root, IsSurvivorDetected)
    (broadcast,) = leaves_of(root, BroadcastSurvivorTF)
    (notify,) = leaves_of(root, NotifyBase)
    assert found.detector is detect and broadcast.detector is detect
    assert notify.detector is detect and notify.broadcaster is broadcast
    with_zones = [b for b in root.iterate() if hasattr(b, "zone_manager")]
    assert len(with_zones) == 7
    assert all(b.zone_manager is zones for b in with_zones)

    survivor_found = broadcast.parent
    assert isinstance(survivor_found, py_trees.composites.Sequence) and survivor_found.memory
    oneshot = leaves_of(root, NavigateToBase)[0].parent
    assert isinstance(oneshot, py_trees.decorators.OneShot)
    assert oneshot.policy == py_trees.common.OneShotPolicy.ON_COMPLETION
    assert isinstance(root, py_trees.composites.Selector) and not root.memory


@pytest.fixture
def mission_servers(tmp_path) -> Iterator[NodeProcess]:
    """The three fake servers; yields the navigation server (its output lists the goals)."""
    with (NodeProcess([str(NODES / "scripted_navigate_server.py"), "--delay", "0.2"], "nav",
                      log_dir=tmp_path) as nav,
          NodeProcess([str(NODES / "detect_echo_server.py")], "detect", log_dir=tmp_path) as det,
          NodeProcess([str(NODES / "delayed_report_server.py"), "--delay", "0.2"], "report",
                      log_dir=tmp_path) as rep):
        for process in (nav, det, rep):
            process.wait_for_output("ready")
        yield nav


@pytest.mark.ros
def test_seed_tree_runs_the_whole_mission(repo_root, ros: tuple, mission_servers: NodeProcess,
                                          capfd: pytest.CaptureFixture) -> None:
    from sar_interfaces.srv import DetectSurvivor as DetectSurvivorSrv
    from sar_interfaces.srv import ReportSurvivor

    node, executor = ros
    zones = spec_zone_manager()
    tree = tree_on(node, load_seed(repo_root, zones))
    frames = TfStaticRecorder(node)
    wait_for_action_server(node, executor)
    wait_for_service(node, executor, DetectSurvivorSrv, "/detect_survivor")
    wait_for_service(node, executor, ReportSurvivor, "/report_survivor")

    # The root is SUCCESS after every zone (Patrol succeeds); the mission is over when the
    # return to base is.
    (base,) = leaves_of(tree.root, NavigateToBase)
    tree.tick()
    spin_until(executor, lambda: base.status == Status.SUCCESS
               or tree.root.status == Status.FAILURE, 30.0, step=tree.tick)
    assert tree.root.status == Status.SUCCESS
    for _ in range(20):  # the rest state: SUCCESS, no new goal
        executor.spin_once(timeout_sec=0.02)
        tree.tick()
    assert tree.root.status == Status.SUCCESS

    goals = re.findall(r"goal \d+: x=(\S+) y=(\S+)", mission_servers.output)
    assert goals == [("-3.00", "3.00"), ("3.50", "3.00"), ("4.00", "-3.00"),
                     ("-3.50", "-3.00"), ("0.00", "0.00")]
    assert spin_until(executor, lambda: frames.child_frames() == {"survivor_1"}, 5.0)
    err = capfd.readouterr().err
    for line in ("--- Zone 1/4: zone_a (-3.00, 3.00) ---", "Reached zone_a.",
                 "Reported survivor_1 at (1.50, -2.00): acknowledged.",
                 "No survivor found at zone_b.", "No survivor found at zone_d.",
                 "--- Zone 4/4: zone_d (-3.50, -3.00) ---",
                 "All zones visited. Returning to base.", "Reached base station."):
        assert err.count(line) == 1, line
