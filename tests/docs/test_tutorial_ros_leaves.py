"""The plugin tutorial's ROS leaves, in a tree, against real servers started by the test."""

import re
import threading
import time
from pathlib import Path
from typing import Any

import pytest
from py_trees.common import Status

from sar_framework.testing.ros_harness import tick_until_done, tree_on
from sar_framework.testing.spin import spin_until

REPO = Path(__file__).resolve().parents[2]
LEAVES = REPO / "trees" / "tutorials" / "plugins" / "ros_leaves.py"
TUTORIAL = REPO / "docs" / "tutorials" / "02_writing_a_plugin.md"
OUTER_S = 30.0  # outer safety bound: the servers answer within a second


@pytest.fixture
def servers(sar_ros_node):
    """A countdown action, a reset service and a latched "go" topic, on their own thread."""
    from rclpy.action import ActionServer
    from rclpy.executors import MultiThreadedExecutor
    from rclpy.node import Node
    from rclpy.qos import DurabilityPolicy, QoSProfile
    from std_msgs.msg import String
    from std_srvs.srv import Trigger
    from tutorial_interfaces.action import Countdown

    node, executor = sar_ros_node
    server = Node("tutorial_servers", context=node.context)

    def count(handle: Any) -> Any:
        for remaining in range(handle.request.start, 0, -1):
            handle.publish_feedback(Countdown.Feedback(remaining=remaining))
            time.sleep(handle.request.period)
        handle.succeed()
        return Countdown.Result(steps=handle.request.start, message="zero")

    def reset(_request: Any, response: Any) -> Any:
        response.success, response.message = True, "counter reset"
        return response

    ActionServer(server, Countdown, "countdown", execute_callback=count)
    server.create_service(Trigger, "reset_counter", reset)
    latched = QoSProfile(depth=10, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    server.create_publisher(String, "go", latched).publish(String(data="go"))
    spinner = MultiThreadedExecutor(context=node.context)
    spinner.add_node(server)
    thread = threading.Thread(target=spinner.spin, daemon=True)
    thread.start()
    yield node, executor
    spinner.shutdown()
    thread.join(timeout=10.0)  # outer safety bound
    server.destroy_node()


def test_the_tutorial_leaves_run_in_a_tree_against_their_servers(servers, sar_tree) -> None:
    node, executor = servers
    run = sar_tree(f"""
        format: 1
        name: ros_leaves
        plugins: [{LEAVES}]
        root:
          sequence:
            name: All
            memory: true
            children:
              - HeardGo: {{name: Go}}
              - ResetCounter: {{name: Reset}}
              - AskCountdown: {{name: Count, start: 3, period: 0.05}}
    """)
    tree = tree_on(node, run.root)
    leaves = {b.name: b for b in run.root.iterate()}
    go = leaves["Go"]  # a condition answers in its tick: first let the latched "go" arrive
    assert spin_until(executor, lambda: go.check(go.last_message), OUTER_S), "no 'go' heard"
    assert tick_until_done(executor, tree, OUTER_S) == Status.SUCCESS
    said = {name: b.feedback_message for name, b in leaves.items()}
    assert said["Reset"] == "counter reset"
    assert said["Count"] == "counted 3 steps"


def test_the_tutorial_shows_the_leaves_and_this_test_as_they_are() -> None:
    text = TUTORIAL.read_text(encoding="utf-8")
    for path in (LEAVES, Path(__file__).resolve()):
        shown = re.search(rf"^```python\n# {re.escape(str(path.relative_to(REPO)))}\n(.*?)^```",
                          text, re.MULTILINE | re.DOTALL)
        assert shown is not None, f"the tutorial does not show {path.name}"
        assert shown.group(1) == path.read_text(encoding="utf-8"), f"{path.name} changed"
