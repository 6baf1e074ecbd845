"""Set-up shared by the port tests: the port test plugins and a clean blackboard.

Import the fixtures into a test module to use them (``port_registry`` is the fixture
``registry``)::

    from .port_setup import clean_blackboard, port_registry  # noqa: F401 (pytest fixtures)
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest
from py_trees.blackboard import Blackboard

from sar_framework.engine.registry import Registry, discover

from .conftest import GENERIC_PLUGINS, HERE

#: Test plugins that declare ports (Plan, Follow...).
PORT_PLUGINS = HERE / "plugins_for_tests" / "ports"

#: A tree that plans into ``{path}`` and follows it in the subtree ``FollowIt``.
PLAN_AND_FOLLOW = """
format: 1
blackboard:
  goal: {type: geometry_msgs/msg/Point, description: Where to go.}
  start: {type: geometry_msgs/msg/Point}
  path: {type: nav_msgs/msg/Path}
  steps: {type: int, initial: 0}
root:
  sequence:
    memory: true
    children:
      - Plan: {goal: "{goal}", path: "{path}"}
      - subtree: {tree: FollowIt, ports: {route: "{path}"}, autoremap: true}
subtrees:
  FollowIt:
    ports:
      route: {type: nav_msgs/msg/Path}
    root:
      Follow: {path: "{route}", steps: "{=}"}
"""


@pytest.fixture(scope="module", name="registry")
def port_registry() -> Registry:
    """The generic test plugins plus the ones that declare ports."""
    reg = discover([GENERIC_PLUGINS, PORT_PLUGINS], builtins=False, entry_points=False)
    assert reg.diagnostics == []
    return reg


@pytest.fixture(autouse=True)
def clean_blackboard() -> Iterator[None]:
    """Empty py_trees' blackboard before and after each test."""
    Blackboard.clear()
    yield
    Blackboard.clear()


def write_tree(tmp_path: Path, text: str) -> Path:
    """Write ``format: 1`` and ``text`` to ``tmp_path/tree.yaml``; return its path."""
    path = tmp_path / "tree.yaml"
    path.write_text("format: 1\n" + text)
    return path
