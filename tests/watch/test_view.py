"""The watch frame, rendered by rich from real status messages of a ticking tree."""

from __future__ import annotations

import json
from pathlib import Path

import py_trees
import pytest
from sar_testing.spin import ros_node, spin_until

from sar_framework import load_tree
from sar_framework.runner.tree_status import (
    STATUS_TOPIC,
    StatusFormatError,
    TreeStatusPublisher,
    decode_status,
)
from sar_framework.watch.command import WatchState
from sar_framework.watch.view import frame

pytestmark = pytest.mark.ros

HERE = Path(__file__).resolve().parent
TREE_FILE = HERE / "watched.yaml"


@pytest.fixture
def messages() -> list[str]:
    """The status messages of three ticks, received over DDS from a real publisher."""
    from std_msgs.msg import String

    py_trees.blackboard.Blackboard.clear()
    loaded = load_tree(TREE_FILE, plugin_paths=[HERE / "watch_leaves.py"])
    tree = py_trees.trees.BehaviourTree(loaded.root)
    received: list[str] = []
    with ros_node("watch_view_test") as (node, executor):
        node.create_subscription(String, STATUS_TOPIC, lambda m: received.append(m.data), 10)
        TreeStatusPublisher(node, loaded.spec, loaded.behaviours,
                            complete=lambda: tree.root.status == py_trees.common.Status.SUCCESS
                            ).attach(tree)
        spin_until(executor, lambda: node.count_subscribers(STATUS_TOPIC) > 0, timeout=5.0)
        for _ in range(4):
            tree.tick()
            executor.spin_once(timeout_sec=0.05)
        spin_until(executor, lambda: len(received) >= 4, timeout=10.0)
    return received


def render(document: dict, rate: float | None = None) -> tuple[str, str]:
    from rich.console import Console

    console = Console(record=True, width=100, force_terminal=True, color_system="standard")
    console.print(frame(document, rate, source="test"))
    return console.export_text(styles=False, clear=False), console.export_text(styles=True)


def test_a_running_tick_shows_names_statuses_branch_and_blackboard(messages) -> None:
    first = decode_status(messages[0])
    assert first["tick"] == 1 and first["tree"] == "watched"
    plain, styled = render(first, 4.0)
    lines = plain.splitlines()
    assert lines[0].startswith("watched  tick 1  4.0 ticks/s")
    assert "* Root [selector]" in plain
    assert "✕ Refuse? [Refuse]  refused on purpose" in plain
    assert "* CountTicks  tick 1 of 3" in plain
    assert "- Second [CountTicks]" in plain  # not ticked yet
    assert "running branch: Root → Work → CountTicks" in plain
    assert "/ticks_counted" in plain and "1" in plain.split("/ticks_counted")[1].splitlines()[0]
    # colours: RUNNING bold yellow, FAILURE red, SUCCESS green (ANSI SGR codes)
    assert "\x1b[1;33m* CountTicks" in styled
    assert "\x1b[31m✕ Refuse?" in styled
    assert "mission over" not in plain


def test_the_last_tick_shows_the_verdict(messages) -> None:
    third = decode_status(messages[2])
    assert third["complete"] is True and third["status"] == "SUCCESS"
    plain, styled = render(third)
    assert "✓ Root [selector]" in plain and "✓ Second [CountTicks]  tick 1 of 1" in plain
    assert "running branch: none" in plain
    assert "mission over: SUCCESS" in plain
    assert "\x1b[32m✓ Second" in styled


def test_visited_flags_follow_the_tick(messages) -> None:
    fourth = decode_status(messages[3])
    visited = {n["name"]: n["visited"] for n in fourth["nodes"]}
    # the memory sequence was complete: a new tick runs it from the start
    assert visited["Root"] and visited["Refuse?"] and visited["Work"]
    assert [n["depth"] for n in fourth["nodes"]] == [0, 1, 1, 2, 2]


def test_tick_rate_from_arrival_times() -> None:
    state = WatchState()
    document = {"format": 1, "tree": "t", "tick": 0, "nodes": []}
    for i in range(5):
        state.take(json.dumps({**document, "tick": i * 2}), now=10.0 + i * 0.5)
    assert state.ticks_per_s() == pytest.approx(4.0)
    state.take("not json", now=13.0)
    assert state.rejected == 1 and state.received == 5


def test_a_foreign_message_is_refused() -> None:
    with pytest.raises(StatusFormatError):
        decode_status('{"format": 99}')
    with pytest.raises(StatusFormatError):
        decode_status("hello")
