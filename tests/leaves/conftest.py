"""The toolkit tests' ROS fixture: a node, its executor, a server node on its own thread."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest

from sar_framework.testing.ros_harness import TreeMaker

from .servers import server_thread


@pytest.fixture
def ros(sar_ros_node: tuple[Any, Any]) -> Iterator[tuple[Any, Any, Any, TreeMaker]]:
    """``(node, executor, server node, tree maker)``; the trees are shut down afterwards."""
    node, executor = sar_ros_node
    trees = TreeMaker(node)
    with server_thread(node) as server:
        yield node, executor, server, trees
        trees.shutdown()
