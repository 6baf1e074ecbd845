"""Nav2's leaves log a failure, never a success, on the node's logger (as Nav2's BT nodes).

rclpy's logger looks up its caller's source file on every call (``inspect``), some
milliseconds on a loaded machine: a line per success inside the 10 ms tick of a navigator
tree put the tick's p99 far over 2 ms (benchmarks/bench_nav2_ticks.py).
"""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace
from typing import Any

import pytest
from py_trees.common import Status

from sar_framework.engine.api import load_tree

pytest.importorskip("nav2_msgs.srv", reason="needs the full nav2_msgs")


class Logger:
    """Records what is logged, by level."""

    def __init__(self) -> None:
        self.lines: list[tuple[str, str]] = []

    def __getattr__(self, level: str) -> Any:
        return lambda message, **_kw: self.lines.append((level, str(message)))


class Done:
    """A service future already answered."""

    def __init__(self, result: Any) -> None:
        self._result = result

    def done(self) -> bool:
        return True

    def exception(self) -> None:
        return None

    def result(self) -> Any:
        return self._result


class Client:
    def __init__(self, srv_type: Any, name: str) -> None:
        self.srv_type = srv_type
        self.service_name = f"/{name}"  # rclpy's Client gives the resolved name

    def service_is_ready(self) -> bool:
        return True

    def call_async(self, _request: Any) -> Done:
        return Done(self.srv_type.Response())


class Node:
    """The little of ``rclpy.node.Node`` a Nav2 service leaf uses."""

    def __init__(self) -> None:
        self.logger = Logger()

    def get_logger(self) -> Logger:
        return self.logger

    def create_client(self, srv_type: Any, name: str) -> Client:
        return Client(srv_type, name)

    def get_clock(self) -> Any:
        return SimpleNamespace(now=lambda: SimpleNamespace(nanoseconds=0))

    def has_parameter(self, _name: str) -> bool:
        return False

    def destroy_client(self, _client: Any) -> None:
        pass


@pytest.mark.parametrize(("service", "expected", "logged"), [
    ("local_costmap/clear_entirely_local_costmap", Status.SUCCESS, []),
    ("", Status.FAILURE, [("info", "Clear: no service_name given")]),
])
def test_a_success_is_not_logged_a_failure_is(tmp_path: Path, service: str,
                                              expected: Status, logged: list) -> None:
    tree = tmp_path / "t.yaml"
    tree.write_text("format: 1\nroot:\n  ClearEntireCostmap: {name: Clear, service_name: "
                    f"'{service}'}}\n")
    leaf = load_tree(tree, {}).root
    node = Node()
    leaf.setup(node=node)
    for _ in range(2):
        leaf.tick_once()
    assert leaf.status == expected
    assert sorted(set(node.logger.lines)) == logged
