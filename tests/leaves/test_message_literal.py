"""A message literal bound to a port is read by a toolkit ROS leaf as the message itself."""

from __future__ import annotations

from typing import Any

from py_trees.blackboard import Blackboard

from sar_framework.engine.building.port_values import PortValues
from sar_framework.engine.message_literals import message_literal
from sar_framework.engine.ports import InputPort, PortBinding
from sar_framework.leaves import RosLeaf
from sar_framework.leaves.message_literal import to_message

POSE = "geometry_msgs/msg/PoseStamped"


class _Reader(RosLeaf):
    def update(self) -> Any:
        raise NotImplementedError


def test_a_ros_leaf_reads_the_message_stamped_now(sar_ros_node: tuple[Any, Any]) -> None:
    node, _executor = sar_ros_node
    literal = message_literal(POSE, {"x": 1.0, "y": 2.0, "yaw": 0.0})
    Blackboard.storage["/stored"] = message_literal(POSE, "0;odom;3;4;0;0;0;0;1")
    ports = PortValues("reader", {
        "goal": PortBinding(InputPort("goal", POSE), value=literal),
        "other": PortBinding(InputPort("other", POSE), key="/stored"),
    })
    try:
        leaf = _Reader("reader", ports=ports)
        assert ports.get("goal") is literal  # plain data until a node can stamp it
        before = node.get_clock().now().nanoseconds
        leaf.setup(node=node)
        goal = ports.get("goal")
        assert type(goal).__name__ == "PoseStamped"
        assert (goal.pose.position.x, goal.pose.position.y, goal.pose.orientation.w) == (
            1.0, 2.0, 1.0)
        assert goal.header.frame_id == "map"
        stamp = goal.header.stamp.sec * 10**9 + goal.header.stamp.nanosec
        assert stamp >= before > 0
        assert ports.get("goal") is not goal  # a new message per read
        other = ports.get("other")
        assert other.header.frame_id == "odom" and other.pose.position.y == 4.0
        assert (other.header.stamp.sec, other.header.stamp.nanosec) == (0, 0)
    finally:
        Blackboard.storage.pop("/stored", None)


def test_nested_lists_of_messages_are_built() -> None:
    path = to_message(message_literal("nav_msgs/msg/Path", {"poses": [
        {"pose": {"position": {"x": 1}}}, {"header": {"frame_id": "odom"}}]}))
    assert [p.pose.position.x for p in path.poses] == [1.0, 0.0]
    assert path.poses[1].header.frame_id == "odom" and path.header.frame_id == "map"
    assert path.header.stamp.sec == 0  # no clock: a 'now' stamp stays zero
