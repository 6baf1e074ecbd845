"""The blackboard entries through a real runner: the status stream, a late joiner, the view."""

from __future__ import annotations

import json
import time
from pathlib import Path

import pytest
from sar_testing.processes import NodeProcess
from sar_testing.spin import ros_node, spin_until

from sar_framework.runner.entry_values import apply_entries
from sar_framework.runner.tree_status import STATUS_TOPIC, decode_status
from sar_framework.watch.command import WatchState
from sar_framework.watch.view import frame

pytestmark = pytest.mark.ros

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
MISSION_PARAMS = REPO / "config" / "mission_params.yaml"


def runner(tree: Path, status: Path) -> list[str]:
    return ["-m", "sar_framework.runner.node", "--ros-args", "--params-file",
            str(MISSION_PARAMS), "-p", f"tree:={tree}",
            "-p", f"plugin_path:={HERE / 'entry_leaves.py'}", "-p", "seed_amcl:=false",
            "-p", f"status_file:={status}", "-p", "exit_on_completion:=true",
            "-p", "completion:=once", "-p", "tick_rate_hz:=20.0"]


def render(document: dict) -> str:
    from rich.console import Console

    console = Console(record=True, width=120, force_terminal=True, color_system="standard")
    console.print(frame(document, 20.0, source="test"))
    return console.export_text(styles=False)


def test_entries_stream_from_the_runner_to_the_watch_view(tmp_path) -> None:
    from std_msgs.msg import String

    status, start, gate = tmp_path / "status.json", tmp_path / "start", tmp_path / "gate"
    tree = tmp_path / "entries.yaml"
    tree.write_text((HERE / "entries.yaml").read_text()
                    .replace('"START"', json.dumps(str(start)))
                    .replace('"GATE"', json.dumps(str(gate))))
    early: list[str] = []
    late: list[str] = []
    with ros_node("entries_live_test") as (node, executor):
        node.create_subscription(String, STATUS_TOPIC, lambda m: early.append(m.data), 100)
        process = NodeProcess(runner(tree, status), "runner", log_dir=tmp_path).start()
        try:
            # the walk starts once this subscriber has its first message, however late
            # discovery is on a loaded machine, so it sees every step
            spin_until(executor, lambda: len(early) >= 1, timeout=60.0)
            start.touch()
            spin_until(executor, lambda: len(early) >= 20, timeout=60.0)
            # a late joiner: the runner sees a new subscriber and sends every entry again;
            # the tree ends (its gate) once that joiner has its full message, however late
            # discovery is on a loaded machine
            node.create_subscription(String, STATUS_TOPIC, lambda m: late.append(m.data), 100)
            spin_until(executor, lambda: any(decode_status(t)["entries_full"] for t in late),
                       timeout=60.0)
            gate.touch()
            spin_until(executor, lambda: any(decode_status(t)["complete"] for t in early),
                       timeout=30.0)
            # Spin while it delivers its last messages, then wait for its end.
            deadline = time.monotonic() + 60.0  # outer safety bound (about 1 s expected)
            while process.returncode() is None \
                    and time.monotonic() < deadline:  # outer safety bound
                executor.spin_once(timeout_sec=0.05)
            assert process.wait(timeout=10.0) == 0, process.output
        finally:
            process.stop()

    documents = [decode_status(text) for text in early]
    first = documents[0]
    # the first message a subscriber gets is full, whichever tick discovery let it see first
    assert first["entries_full"] is True
    assert {row[0] for row in first["entries"]} == {"count", "label", "where"}
    # later ticks carry only what changed: count and where while the walker walks, nothing
    # while the gate holds; never the constant label
    later = [{row[0] for row in d["entries"]} for d in documents[1:] if not d["entries_full"]]
    assert {"count", "where"} in later and all(names <= {"count", "where"} for names in later)
    # the walker counts its ticks from the tick it started on
    steps = [d for d in documents[1:] if not d["entries_full"]
             and any(row[0] == "count" for row in d["entries"])]
    started = steps[0]["tick"]
    tick = steps[4]["tick"]
    rows = {row[0]: row for row in steps[4]["entries"]}
    assert rows["count"] == ["count", "/count", str(tick - started + 1), "int", "Walker"]
    assert rows["where"] == ["where", "/where", f"Point(x={tick - started + 1}, y=0.5, z=0)",
                             "geometry_msgs/msg/Point", "Walker"]

    late_documents = [decode_status(text) for text in late]
    full = [d for d in late_documents if d["entries_full"]]
    assert full and full[0]["tick"] > 1, [d["tick"] for d in late_documents]
    assert {row[0] for row in full[0]["entries"]} == {"count", "label", "where"}

    final = {}
    for document in documents:
        final = apply_entries(final, document["entries"], full=document["entries_full"])
    assert final["count"]["value"] == "60" and final["label"]["value"] == "'north'"

    state = WatchState()
    for text in late:
        state.take(text, time.monotonic())
    plain = render(state.document)
    assert "entries" in plain
    count_line = next(line for line in plain.splitlines() if line.startswith("count"))
    assert count_line.split()[:4] == ["count", "60", "int", "Walker"]
    assert "Point(x=60, y=0.5, z=0)" in plain and "'north'" in plain

    saved = json.loads(status.read_text())
    assert saved["entries"]["where"] == {"key": "/where", "value": "Point(x=60, y=0.5, z=0)",
                                         "type": "geometry_msgs/msg/Point", "writer": "Walker"}


def test_a_status_without_entries_draws_no_entries_panel() -> None:
    state = WatchState()
    state.take(json.dumps({"format": 1, "tree": "t", "tick": 1, "status": "RUNNING",
                           "nodes": [["0", "Root", "sequence", "RUNNING", "", True]]}), 0.0)
    assert state.entries == {} and "entries" not in render(state.document)
