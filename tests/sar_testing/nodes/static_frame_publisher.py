"""Publish one static frame on /tf_static (RELIABLE, TRANSIENT_LOCAL) and stay alive.

Logs ``sent`` after publishing, so a test can start a late subscriber afterwards.
"""

import rclpy
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
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, rclpy.executors.ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    main()
