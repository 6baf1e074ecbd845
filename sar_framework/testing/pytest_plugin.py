"""The pytest plugin (entry point ``pytest11``): fixtures for testing leaf plugins.

Installing sar_framework makes these fixtures available in every pytest run:

``sar_tree(text, *, context=None, plugin_paths=(), registry=None, blackboard=None)``
    Load a node or tree written as YAML text; returns a
    :class:`~sar_framework.testing.trees.TreeRun` (shut down after the test).
``sar_leaf(plugin, params=None, **same_keywords)``
    The same for one leaf of ``plugin``.
``sar_ros_domain``
    A ROS domain id leased for the session (loopback discovery); sets the environment
    of this process and its children, restores it at the end.
``sar_ros_node``
    ``(node, executor)`` on a fresh rclpy context on that domain.
``sar_mission_stack``
    The embedded simulator and the installed apps' processes on that domain, started and
    ready (:class:`~sar_framework.testing.mission_stack.MissionStack`).

Nothing is imported from ROS until a ROS fixture is used.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

_ROS_ENV = ("ROS_AUTOMATIC_DISCOVERY_RANGE", "ROS_DOMAIN_ID", "ROS_STATIC_PEERS",
            "ROS_LOCALHOST_ONLY", "RMW_IMPLEMENTATION", "PYTHONUNBUFFERED",
            "RCUTILS_COLORIZED_OUTPUT")


@pytest.fixture
def sar_tree() -> Iterator[Callable[..., Any]]:
    """A factory: YAML text (a node or a tree file) -> a loaded TreeRun."""
    from sar_framework.testing.trees import TreeRun, tree_from_yaml

    runs: list[TreeRun] = []

    def make(text: str, **kwargs: Any) -> TreeRun:
        runs.append(tree_from_yaml(text, **kwargs))
        return runs[-1]

    yield make
    for run in runs:
        run.shutdown()


@pytest.fixture
def sar_leaf() -> Iterator[Callable[..., Any]]:
    """A factory: plugin name and params -> a one-leaf TreeRun."""
    from sar_framework.testing.trees import TreeRun, leaf_run

    runs: list[TreeRun] = []

    def make(plugin: str, params: dict[str, Any] | None = None, **kwargs: Any) -> TreeRun:
        runs.append(leaf_run(plugin, params, **kwargs))
        return runs[-1]

    yield make
    for run in runs:
        run.shutdown()


@pytest.fixture(scope="session")
def sar_ros_domain() -> Iterator[int]:
    """A ROS domain id of this session's own, applied to the environment."""
    from sar_framework.testing.ros_env import apply_local_ros_env, lease_domain_id

    saved = {key: os.environ.get(key) for key in _ROS_ENV}
    lease = lease_domain_id()
    apply_local_ros_env(lease.domain_id)
    yield lease.domain_id
    for key, value in saved.items():
        if value is None:
            os.environ.pop(key, None)
        else:
            os.environ[key] = value
    lease.release()


@pytest.fixture
def sar_ros_node(sar_ros_domain: int) -> Iterator[tuple[Any, Any]]:
    """``(node, executor)`` on a fresh rclpy context, on the leased domain."""
    from sar_framework.testing.spin import ros_node

    with ros_node("sar_test") as pair:
        yield pair


@pytest.fixture
def sar_mission_stack(sar_ros_domain: int, tmp_path: Path) -> Iterator[Any]:
    """The simulator and the installed apps' processes, ready."""
    from sar_framework.testing.mission_stack import MissionStack

    with MissionStack(tmp_path / "mission_stack") as stack:
        yield stack
