"""IsPathValid against a real ``is_path_valid`` service (another node, its own thread).

The condition answers in its tick: it waits for the service's answer on a private
executor, at most ``server_timeout``; the tree's executor is not spun meanwhile.
"""

from __future__ import annotations

import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from py_trees.blackboard import Blackboard
from py_trees.common import Status
from sar_testing.spin import ros_node

from sar_framework.engine.api import load_tree

pytestmark = [pytest.mark.ros, pytest.mark.timeout(120)]
pytest.importorskip("nav2_msgs.srv", reason="needs the full nav2_msgs")

TREE = """format: 1
blackboard:
  path: {type: nav_msgs/msg/Path}
root:
  IsPathValid: {path: "{path}", server_timeout: 2000}
"""


@pytest.fixture
def server() -> Iterator[tuple[Any, list[int]]]:
    """A node serving is_path_valid (valid unless the path has 3 poses), spun in a thread."""
    import rclpy
    from nav2_msgs.srv import IsPathValid
    from rclpy.executors import SingleThreadedExecutor

    with ros_node("path_valid_test") as (node, _executor):
        asked: list[int] = []
        serving = rclpy.create_node("planner_stand_in", context=node.context)

        def answer(request: Any, response: Any) -> Any:
            asked.append(len(request.path.poses))
            response.is_valid = len(request.path.poses) != 3
            return response

        serving.create_service(IsPathValid, "is_path_valid", answer)
        spinner = SingleThreadedExecutor(context=node.context)
        spinner.add_node(serving)
        thread = threading.Thread(target=spinner.spin, daemon=True)
        thread.start()
        try:
            yield node, asked
        finally:
            spinner.shutdown()
            thread.join(timeout=5)
            serving.destroy_node()


def test_is_path_valid_asks_the_service_in_its_tick(server: tuple[Any, list[int]],
                                                    tmp_path: Path) -> None:
    from geometry_msgs.msg import PoseStamped
    from nav_msgs.msg import Path as PathMsg

    node, asked = server
    tree = tmp_path / "t.yaml"
    tree.write_text(TREE)
    leaf = load_tree(tree, {}).root
    leaf.setup(node=node)  # waits (1 s at most) for the service to be discovered
    try:
        Blackboard.storage["/path"] = PathMsg(poses=[PoseStamped()] * 2)
        leaf.tick_once()
        assert leaf.status == Status.SUCCESS, leaf.feedback_message
        Blackboard.storage["/path"] = PathMsg(poses=[PoseStamped()] * 3)
        leaf.tick_once()
        assert leaf.status == Status.FAILURE and leaf.feedback_message == "path invalid"
        assert asked == [2, 3]
        del Blackboard.storage["/path"]
        leaf.tick_once()
        assert leaf.status == Status.FAILURE and leaf.feedback_message == "no path"
    finally:
        leaf.shutdown()


def test_is_path_valid_without_a_service_fails_in_its_bound(tmp_path: Path) -> None:
    from nav_msgs.msg import Path as PathMsg

    tree = tmp_path / "t.yaml"
    tree.write_text(TREE.replace("2000", "100"))
    with ros_node("no_planner") as (node, _executor):
        node.declare_parameter("wait_for_service_timeout", 100)
        leaf = load_tree(tree, {}).root
        leaf.setup(node=node)
        try:
            Blackboard.storage["/path"] = PathMsg()
            leaf.tick_once()  # blocks for its 100 ms server_timeout, then fails
            assert leaf.status == Status.FAILURE
            assert leaf.feedback_message == "is_path_valid: no answer in time"
        finally:
            leaf.shutdown()
