"""The Nav2 leaves' shared TF listener: current without the leaf's executor, gone with its node."""

from __future__ import annotations

from typing import Any

from sar_framework.testing.spin import ros_node, spin_until

OUTER_BOUND_S = 20.0  # outer safety bound: discovery and one /tf message take well under 1 s


def broadcast_pose(node: Any, x: float) -> Any:
    """Publish map -> base_link at ``x`` on /tf from ``node``; return the timer."""
    from geometry_msgs.msg import TransformStamped
    from tf2_msgs.msg import TFMessage

    publisher = node.create_publisher(TFMessage, "/tf", 10)

    def publish() -> None:
        transform = TransformStamped()
        transform.header.stamp = node.get_clock().now().to_msg()
        transform.header.frame_id, transform.child_frame_id = "map", "base_link"
        transform.transform.translation.x = x
        transform.transform.rotation.w = 1.0
        publisher.publish(TFMessage(transforms=[transform]))

    return node.create_timer(0.05, publish)


def test_the_pose_arrives_while_the_leafs_executor_is_not_spun() -> None:
    from sar_plugins.nav2._tf import robot_pose, tf_buffer

    with ros_node("tf_listener_leaf") as (leaf, _unspun), \
            ros_node("tf_listener_robot") as (robot, robot_executor):
        tf_buffer(leaf)
        broadcast_pose(robot, 1.5)
        found: list[Any] = []

        def pose_known() -> bool:
            found[:] = [robot_pose(leaf, "map", "base_link")]
            return found[0] is not None

        # Only the robot's executor is spun: the leaf's /tf must arrive by the listener's thread.
        assert spin_until(robot_executor, pose_known, OUTER_BOUND_S), (
            "no map -> base_link in the leaf's buffer while its executor was not spun")
        assert found[0].pose.position.x == 1.5


def test_the_listener_ends_with_its_nodes_context() -> None:
    from sar_plugins.nav2._tf import listener_threads, tf_buffer

    with ros_node("tf_listener_context") as (leaf, _executor):
        tf_buffer(leaf)
        (thread,) = [t for t in listener_threads() if t.name.endswith(":tf_listener_context")]
    thread.join(OUTER_BOUND_S)  # outer safety bound: the thread polls every 0.1 s
    assert not thread.is_alive(), "a TF listener's thread outlived its node's context"


def test_the_listener_ends_with_its_node() -> None:
    from sar_plugins.nav2._tf import listener_threads, tf_buffer

    with ros_node("tf_listener_owner") as (leaf, _executor):
        tf_buffer(leaf)
        (thread,) = [t for t in listener_threads() if t.name.endswith(":tf_listener_owner")]
        names = [name for name, _ in leaf.get_node_names_and_namespaces()]
        leaf.destroy_node()
        thread.join(OUTER_BOUND_S)  # outer safety bound: the thread polls every 0.1 s
        assert not thread.is_alive(), f"the listener's thread outlived its node: {names}"
