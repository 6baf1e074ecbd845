"""A Nav2 action leaf waits for its goal's acknowledgement ``server_timeout`` of ROS time.

Nav2's BtActionNode measures the wait on the node's clock and spins for the answer inside
the tick. The leaf does not block: a loaded machine that runs the next tick late, before the
executor took the answer, must not fail the goal; only the node's clock counts.
"""

from __future__ import annotations

import time
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import pytest
from py_trees.common import Status
from sar_testing.manual_clock import ManualClock

from sar_framework.engine.api import load_tree

spin_action = pytest.importorskip("nav2_msgs.action", reason="needs nav2_msgs").Spin


class Pending:
    """A goal request the server has not answered yet."""

    def __init__(self) -> None:
        self.answer: Any = None

    def done(self) -> bool:
        return self.answer is not None

    def exception(self) -> None:
        return None

    def result(self) -> Any:
        return self.answer

    def add_done_callback(self, _callback: Any) -> None:
        pass


class Client:
    """An action client whose server is there; it records the goals' futures."""

    def __init__(self) -> None:
        self.sent: list[Pending] = []

    def server_is_ready(self) -> bool:
        return True

    def send_goal_async(self, _goal: Any, feedback_callback: Any = None) -> Pending:
        self.sent.append(Pending())
        return self.sent[-1]


def spin_leaf(tmp_path: Path, monkeypatch: pytest.MonkeyPatch
              ) -> tuple[Any, Client, ManualClock, ManualClock]:
    """A Spin leaf (``server_timeout``: Nav2's 20 ms); its node's clock and the wall clock."""
    clock, wall = ManualClock(100.0), ManualClock(1000.0)
    monkeypatch.setattr(time, "monotonic", wall)
    tree = tmp_path / "t.yaml"
    tree.write_text("format: 1\nroot:\n  Spin: {name: Turn, spin_dist: 1.57}\n")
    leaf = load_tree(tree, {}).root
    node = clock.node()
    node.get_logger = lambda: SimpleNamespace(info=lambda *_a, **_k: None)
    node.has_parameter = lambda _name: False
    client = Client()
    leaf._node, leaf._action_type, leaf._client = node, spin_action, client
    return leaf, client, clock, wall


def test_a_late_tick_on_the_wall_clock_is_not_a_late_acknowledgement(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    leaf, client, _clock, wall = spin_leaf(tmp_path, monkeypatch)
    leaf.tick_once()
    assert leaf.status == Status.RUNNING and len(client.sent) == 1
    wall.now += 5.0  # the machine was busy: seconds of wall time, no ROS time
    leaf.tick_once()
    assert leaf.status == Status.RUNNING, leaf.feedback_message
    result = SimpleNamespace(status=4, result=spin_action.Result())  # STATUS_SUCCEEDED
    done = Pending()
    done.answer = result
    client.sent[0].answer = SimpleNamespace(accepted=True, get_result_async=lambda: done)
    leaf.tick_once()
    assert leaf.status == Status.SUCCESS, leaf.feedback_message


def test_an_acknowledgement_missing_past_the_bound_fails_on_the_next_tick(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    leaf, _client, clock, wall = spin_leaf(tmp_path, monkeypatch)
    leaf.tick_once()
    clock.now += 0.019
    wall.now += 1.0
    leaf.tick_once()
    assert leaf.status == Status.RUNNING
    clock.now += 0.8  # one /clock step: the bound passed, the answer may be in the executor
    leaf.tick_once()
    assert leaf.status == Status.RUNNING
    clock.now += 0.8
    leaf.tick_once()
    assert leaf.status == Status.FAILURE
    assert leaf.feedback_message == ("Timed out while waiting for action server to "
                                     "acknowledge goal request for spin")
