"""A runner started in a namespace reads TF from the namespace's ``tf`` topics.

nav2_bringup's multi-robot launch remaps ``/tf`` and ``/tf_static`` to ``tf`` and
``tf_static`` for every node of a robot; the runner's node does the same, so the leaves'
``TransformListener`` (made on that node) follow the robot, not the root.
"""

from __future__ import annotations

import pytest

pytestmark = pytest.mark.ros


@pytest.mark.parametrize(("namespace", "expected"), [
    ("/robot1", {"/robot1/tf", "/robot1/tf_static"}),
    ("/", {"/tf", "/tf_static"}),
])
def test_runner_node_listens_to_its_namespace_tf(namespace: str, expected: set[str]) -> None:
    import rclpy
    from rclpy.context import Context
    from tf2_ros import Buffer, TransformListener

    from sar_framework.runner.node import create_runner_node

    context = Context()
    rclpy.init(args=["x", "--ros-args", "-r", f"__ns:={namespace}"], context=context)
    try:
        node = create_runner_node(context=context)
        TransformListener(Buffer(), node, spin_thread=False)
        topics = {name for name, _ in node.get_subscriber_names_and_types_by_node(
            node.get_name(), node.get_namespace())}
        assert {t for t in topics if t.endswith(("/tf", "/tf_static"))} == expected
        node.destroy_node()
    finally:
        rclpy.try_shutdown(context=context)
