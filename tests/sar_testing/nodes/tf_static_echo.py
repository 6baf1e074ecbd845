"""Subscribe to /tf_static (RELIABLE, TRANSIENT_LOCAL, depth 100) and log what arrives.

For the late-subscriber test: started after the frames were sent, it logs one line per
message, ``tf_static: parent->child,parent->child``, and ``listening`` once subscribed.
"""

import rclpy
from _node_main import spin_until_interrupted
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from tf2_msgs.msg import TFMessage


def main() -> None:
    """Echo until SIGINT."""
    rclpy.init()
    node = Node("tf_static_echo")
    qos = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)

    def echo(message: TFMessage) -> None:
        frames = ",".join(f"{t.header.frame_id}->{t.child_frame_id}" for t in message.transforms)
        node.get_logger().info(f"tf_static: {frames}")

    node.create_subscription(TFMessage, "/tf_static", echo, qos)
    node.get_logger().info("listening")
    spin_until_interrupted(node)


if __name__ == "__main__":
    main()
