"""Publish one static frame on /tf_static (RELIABLE, TRANSIENT_LOCAL) and stay alive.

Logs ``sent`` after publishing, so a test can start a late subscriber afterwards.
"""

import rclpy
from _node_main import spin_until_interrupted
from geometry_msgs.msg import TransformStamped
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from tf2_msgs.msg import TFMessage


def main() -> None:
    """Publish, then spin until SIGINT."""
    rclpy.init()
    node = Node("static_frame_publisher")
    qos = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
    publisher = node.create_publisher(TFMessage, "/tf_static", qos)
    transform = TransformStamped()
    transform.header.frame_id = "map"
    transform.header.stamp = node.get_clock().now().to_msg()
    transform.child_frame_id = "smoke_frame"
    transform.transform.translation.x = 1.25
    transform.transform.rotation.w = 1.0
    publisher.publish(TFMessage(transforms=[transform]))
    node.get_logger().info("sent")
    spin_until_interrupted(node)


if __name__ == "__main__":
    main()
