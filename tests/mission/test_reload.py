"""The runner's ~/reload service over real DDS, called by a real rclpy client (runner/reload.py)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from sar_testing.processes import NodeProcess

from sar_framework.events.event import EventKind
from sar_framework.events.jsonl import EVENTS_FILE, read_events
from sar_framework.testing.spin import call_service, ros_node

ros = pytest.mark.ros
REPO = Path(__file__).resolve().parents[2]
PLUGINS = Path(__file__).resolve().parent / "runner_plugins"
MISSION_PARAMS = REPO / "config" / "mission_params.yaml"


def runner_args(tree: Path, status: Path, *extra: str) -> list[str]:
    args = ["-m", "sar_framework.runner.node", "--ros-args", "--params-file",
            str(MISSION_PARAMS), "-p", f"tree:={tree}", "-p", f"plugin_path:={PLUGINS}",
            "-p", "seed_amcl:=false", "-p", f"status_file:={status}"]
    for item in extra:
        args += ["-p", item]
    return args

TREE = """\
format: 1
name: reloaded
root:
  sequence:
    name: Steps
    memory: true
    children:
      - Countdown: {name: Work, ticks: 160}
      - Countdown: {name: Last, ticks: 0, message: first}
"""
BAD = TREE.replace("Countdown: {name: Last", "Countdwn: {name: Last")
GOOD = TREE.replace("message: first", "message: second").replace(
    "      - Countdown: {name: Last", "      - Countdown: {name: Extra, ticks: 2}\n"
    "      - Countdown: {name: Last")


def reload(node: object, executor: object) -> tuple[bool, str]:
    from std_srvs.srv import Trigger

    # A reload is not idempotent (each one is an event): sent once, answered once.
    response = call_service(node, executor, Trigger, "/sar_mission_runner/reload",
                            Trigger.Request(), timeout=20.0, resend_after=None,
                            discovery_timeout=30.0)
    assert response is not None, "no answer from /sar_mission_runner/reload"
    return response.success, response.message


@ros
def test_reload_service_refuses_a_bad_edit_then_swaps_a_good_one(tmp_path: Path) -> None:
    status = tmp_path / "status.json"
    tree = tmp_path / "tree.yaml"
    tree.write_text(TREE)
    process = NodeProcess(runner_args(tree, status, "exit_on_completion:=true",
                                      "completion:=once", "tick_rate_hz:=20.0"),
                          "runner", log_dir=tmp_path).start()
    try:
        process.wait_for_output("Ticking", timeout=30)
        with ros_node("reload_client") as (node, executor):
            tree.write_text(BAD)
            ok, message = reload(node, executor)
            assert not ok
            assert f"{tree}:9:9" in message and "Countdwn" in message, message
            assert "refused, the tree goes on" in message
            tree.write_text(GOOD)
            ok, message = reload(node, executor)
            assert ok, message
            assert "1 added (Extra); 1 changed (Last); 2 kept" in message, message
        code = process.wait(timeout=40)
    finally:
        process.stop()
    output = process.output
    assert code == 0, output
    assert "Traceback" not in output and "Mission complete." in output
    events = read_events(status.with_name(EVENTS_FILE))
    kinds = [e.kind for e in events]
    assert kinds.count(EventKind.RELOAD_REFUSED) == 1 and kinds.count(EventKind.TREE_SWAPPED) == 1
    assert kinds.index(EventKind.RELOAD_REFUSED) < kinds.index(EventKind.TREE_SWAPPED)
    verdicts = [(e.node_name, e.node_uid, e.message) for e in events
                if e.kind == EventKind.STATUS and e.status == "SUCCESS"]
    # Work was kept: it ran its 160 ticks once, through both reloads; then the new leaves.
    assert verdicts == [("Work", "0.0", "done after 160 ticks (4 zones)"),
                        ("Extra", "0.1", "done after 2 ticks (4 zones)"),
                        ("Last", "0.2", "second")]
    started = [e.node_name for e in events if e.kind == EventKind.STATUS and e.status == "RUNNING"]
    assert started.count("Work") == 1
    doc = json.loads(status.read_text())
    assert doc["nodes"] == {"0": "SUCCESS", "0.0": "SUCCESS", "0.1": "SUCCESS", "0.2": "SUCCESS"}
