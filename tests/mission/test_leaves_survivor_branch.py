"""The SurvivorFound branch: one survivor id per detection, and why its Sequence needs memory.

Tree under test (hand-built; the report server answers 1 s late so NotifyBase stays RUNNING
for many ticks)::

    Sequence "Branch" memory=True
    ├── DetectSurvivor
    └── Sequence "SurvivorFound" memory=<True|False>
        ├── IsSurvivorDetected?
        ├── BroadcastSurvivorTF
        └── NotifyBase
"""

from __future__ import annotations

import threading
from collections.abc import Iterator

import py_trees
import pytest
from leaves.servers import server_thread
from py_trees.common import Status
from sar_plugins.sar.leaves.broadcast_survivor_tf import BroadcastSurvivorTF
from sar_plugins.sar.leaves.detect_survivor import DetectSurvivor
from sar_plugins.sar.leaves.is_survivor_detected import IsSurvivorDetected
from sar_plugins.sar.leaves.notify_base import NotifyBase
from sar_plugins.sar.zone_manager import ZoneManager
from sar_testing.leaf_harness import (
    NODES,
    OutputMark,
    TfStaticRecorder,
    TreeMaker,
    spec_zone_manager,
    tick_until_done,
    tree_on,
    wait_for_service,
)
from sar_testing.processes import NodeProcess
from sar_testing.spin import spin_until

from sar_framework.testing import declared_leaf

pytestmark = pytest.mark.ros
REPORT_DELAY_S = 1.0


@pytest.fixture(scope="module")
def servers(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[NodeProcess, NodeProcess]]:
    """The detect echo server (survivor at (1.5, -2.0) in zone_a) and a slow report server."""
    log_dir = tmp_path_factory.mktemp("branch")
    with (NodeProcess([str(NODES / "detect_echo_server.py")], "detect", log_dir=log_dir) as det,
          NodeProcess([str(NODES / "delayed_report_server.py"), "--delay", str(REPORT_DELAY_S)],
                      "report", log_dir=log_dir) as rep):
        det.wait_for_output("ready")
        rep.wait_for_output("ready")
        yield det, rep


@pytest.fixture
def branch_env(module_ros: tuple, servers: tuple) -> Iterator[tuple]:
    """``(node, make_tree, executor, report_mark)`` with both services discovered."""
    from sar_interfaces.srv import DetectSurvivor as DetectSurvivorSrv
    from sar_interfaces.srv import ReportSurvivor

    node, executor = module_ros
    wait_for_service(node, executor, DetectSurvivorSrv, "/detect_survivor")
    wait_for_service(node, executor, ReportSurvivor, "/report_survivor")
    make_tree = TreeMaker(node)
    yield node, make_tree, executor, OutputMark(servers[1])
    make_tree.shutdown()


def build_branch(zones: ZoneManager, *, memory: bool,
                 response_timeout_s: float = 10.0) -> tuple[py_trees.composites.Sequence,
                                                            NotifyBase]:
    detect = declared_leaf(DetectSurvivor, "DetectSurvivor", zone_manager=zones)
    broadcast = declared_leaf(BroadcastSurvivorTF, zone_manager=zones, detector=detect)
    notify = declared_leaf(NotifyBase, "NotifyBase", detector=detect, broadcaster=broadcast,
                        response_timeout_s=response_timeout_s)
    found = py_trees.composites.Sequence("SurvivorFound", memory=memory, children=[
        IsSurvivorDetected("IsSurvivorDetected?", detector=detect), broadcast, notify,
    ])
    return py_trees.composites.Sequence("Branch", memory=True, children=[detect, found]), notify


def run_counting_notify_ticks(executor, tree, notify: NotifyBase, timeout: float) -> int:
    running_ticks = 0

    def step() -> None:
        nonlocal running_ticks
        tree.tick()
        running_ticks += notify.status == Status.RUNNING

    tree.tick()
    spin_until(executor, lambda: tree.root.status in (Status.SUCCESS, Status.FAILURE), timeout,
               step=step)
    return running_ticks


def run_branch(branch_env: tuple, *, memory: bool
               ) -> tuple[ZoneManager, TfStaticRecorder, py_trees.behaviour.Behaviour, int]:
    """Run the branch to its end: the zones, the frames seen, NotifyBase, its RUNNING ticks."""
    node, make_tree, executor, _report = branch_env
    zones = spec_zone_manager()
    root, notify = build_branch(zones, memory=memory)
    tree = make_tree(root)
    frames = TfStaticRecorder(node)
    running_ticks = run_counting_notify_ticks(executor, tree, notify, 10.0)
    assert root.status == Status.SUCCESS
    assert running_ticks >= 10, "the report server should keep NotifyBase RUNNING for a while"
    return zones, frames, notify, running_ticks


def test_memory_true_allocates_one_id_and_reports_it(branch_env: tuple) -> None:
    executor, report = branch_env[2], branch_env[3]
    zones, frames, notify, _ = run_branch(branch_env, memory=True)
    assert notify.feedback_message == "Reported survivor_1 at (1.50, -2.00): acknowledged."
    assert spin_until(executor, lambda: frames.child_frames() == {"survivor_1"}, 5.0)
    assert zones.next_survivor_id() == "survivor_2", "exactly one id was allocated"
    assert report.text.count("report: ") == 1
    assert "report: survivor_1 at (1.50, -2.00) frame=map" in report.text


def test_memory_false_reallocates_ids_while_notify_is_running(branch_env: tuple) -> None:
    """Why SurvivorFound is memory=True: without memory each RUNNING tick re-ticks the earlier
    siblings, and every re-tick of BroadcastSurvivorTF allocates (and broadcasts) a new id."""
    executor, report = branch_env[2], branch_env[3]
    zones, frames, _, running_ticks = run_branch(branch_env, memory=False)
    duplicates = int(zones.next_survivor_id().removeprefix("survivor_")) - 1
    assert duplicates > running_ticks // 2, "each RUNNING tick should allocate another id"
    assert spin_until(executor, lambda: len(frames.child_frames()) > 1, 5.0)
    # NotifyBase itself stayed RUNNING (not re-initialised): one report, with the first id.
    assert report.text.count("report: ") == 1
    assert "report: survivor_1 " in report.text


def test_an_unanswered_request_is_sent_again_and_the_first_answer_wins(
        branch_env: tuple) -> None:
    """A reply lost right after discovery must not stall a leaf until its bound: the call
    re-sends, keeping the earlier request pending, so a slow server's answer still counts."""
    from sar_interfaces.srv import ReportSurvivor

    from sar_framework.leaves import PolledServiceCall

    node, _make_tree, executor, report = branch_env
    call = PolledServiceCall(node, ReportSurvivor, "/report_survivor", server_timeout_s=5.0,
                             response_timeout_s=5.0, resend_after_wall_s=0.3)
    request = ReportSurvivor.Request(survivor_id="survivor_9")
    request.location.header.frame_id = "map"
    results = []
    try:
        call.start()
        assert spin_until(executor, lambda: bool(results), 5.0,
                          step=lambda: results.extend(filter(None, [call.poll(lambda: request)])))
    finally:
        call.destroy()
    (result,) = results
    assert result.error is None and result.response.acknowledged
    # the server (1.0 s per answer) saw the request and at least one resend
    assert report.text.count("report: survivor_9 ") >= 2


SILENT_SERVICE = "/report_survivor_silent"


def test_unanswered_report_fails_after_its_bound(branch_env: tuple) -> None:
    """Once its bound had passed and its resend (after 2 wall seconds) had a tick too."""
    from rclpy.callback_groups import ReentrantCallbackGroup
    from sar_interfaces.srv import ReportSurvivor

    node, make_tree, executor, _report = branch_env
    root, notify = build_branch(spec_zone_manager(), memory=True, response_timeout_s=0.5)
    notify.service_name = SILENT_SERVICE
    asked: list[str] = []
    released = threading.Event()

    def hold(request: ReportSurvivor.Request, response: ReportSurvivor.Response
             ) -> ReportSurvivor.Response:
        asked.append(request.survivor_id)
        released.wait(60.0)  # outer safety bound: answered only once the test is over
        return response

    with server_thread(node) as server:
        server.create_service(ReportSurvivor, SILENT_SERVICE, hold,
                              callback_group=ReentrantCallbackGroup())
        try:
            wait_for_service(node, executor, ReportSurvivor, SILENT_SERVICE)
            # outer safety bound: the failure comes about 2 s after the request
            assert tick_until_done(executor, make_tree(root), 30.0) == Status.FAILURE
        finally:
            released.set()
    assert notify.feedback_message == f"no response from {SILENT_SERVICE} within 0.5 s"
    assert asked and set(asked) == {"survivor_1"}  # the request (and its resend) arrived


def test_nothing_to_report_without_a_detection(ros: tuple) -> None:
    node, _executor = ros
    zones = spec_zone_manager()
    detect = declared_leaf(DetectSurvivor, "DetectSurvivor", zone_manager=zones)
    broadcast = declared_leaf(BroadcastSurvivorTF, zone_manager=zones, detector=detect)
    notify = declared_leaf(NotifyBase, "NotifyBase", detector=detect, broadcaster=broadcast)
    tree = tree_on(node, py_trees.composites.Sequence("S", memory=True,
                                                      children=[broadcast, notify]))
    tree.tick()
    assert broadcast.status == Status.FAILURE
    assert broadcast.feedback_message == "no survivor detected to broadcast"
    notify.tick_once()
    assert notify.status == Status.FAILURE
    assert notify.feedback_message == "no survivor detected to report"


REFUSING_SERVICE = "/report_survivor_refusing"


def test_a_refused_report_is_logged_as_a_refusal_never_as_no_survivor(
        branch_env: tuple, repo_root, capfd: pytest.CaptureFixture[str]) -> None:
    """The reference tree's HandleDetection branch, against a base that refuses every report."""
    from sar_interfaces.srv import ReportSurvivor

    from sar_framework import load_tree

    node, _make_tree, executor, _report = branch_env

    from sar_plugins.sar.events import SarKind

    from sar_framework.events.emitter import EventEmitter
    from sar_framework.events.event import EventKind

    def refuse(_request: ReportSurvivor.Request,
               response: ReportSurvivor.Response) -> ReportSurvivor.Response:
        response.acknowledged = False
        response.reason = "the base is full"
        return response

    service = node.create_service(ReportSurvivor, REFUSING_SERVICE, refuse)
    try:
        loaded = load_tree(repo_root / "trees" / "search_and_rescue.yaml",
                           context={"zone_manager": spec_zone_manager()})
        by_name = {b.name: b for b in loaded.root.iterate()}
        by_name["NotifyBase"].service_name = REFUSING_SERVICE
        patrol, detect, handle = by_name["Patrol"], by_name["DetectSurvivor"], \
            by_name["HandleDetection"]
        patrol.remove_child(detect)
        patrol.remove_child(handle)
        events = EventEmitter()
        tree = TreeMaker(node, events)(py_trees.composites.Sequence("Branch", memory=True,
                                                                    children=[detect, handle]))
        assert tick_until_done(executor, tree, 10.0) == Status.SUCCESS
        tree.shutdown()
    finally:
        node.destroy_service(service)
    logged = capfd.readouterr().err
    assert "Report for survivor_1 refused by base: the base is full" in logged
    told = [(e.kind, e.value("survivor_id"), e.message) for e in events.emitted
            if e.kind != SarKind.DETECTION]
    assert told == [
        (SarKind.SURVIVOR_BROADCAST, "survivor_1",
         "Broadcast static TF map -> survivor_1 at (1.50, -2.00)."),
        (SarKind.SURVIVOR_REFUSED, "survivor_1", "the base is full"),
        (EventKind.NOTE, "", "Report for survivor_1 refused by base: the base is full")]
    assert "No survivor found" not in logged
    assert by_name["LogNoDetection"].status == Status.INVALID, "never ticked"
