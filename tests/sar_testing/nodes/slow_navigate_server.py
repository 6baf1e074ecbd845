"""A minimal NavigateToPose server for the environment smoke test.

Accepts every goal and cancel, publishes feedback every 50 ms with a shrinking
``distance_remaining``, and never finishes by itself: the client must cancel.
"""

import time

import rclpy
from _node_main import serve_navigate_to_pose
from nav2_msgs.action import NavigateToPose
from rclpy.node import Node


def main() -> None:
    """Serve until SIGINT."""
    rclpy.init()
    node = Node("slow_navigate_server")

    def execute(goal_handle):
        feedback = NavigateToPose.Feedback()
        distance = 10.0
        node.get_logger().info("goal executing")
        while not goal_handle.is_cancel_requested:
            feedback.distance_remaining = distance
            feedback.current_pose.header.frame_id = "map"
            goal_handle.publish_feedback(feedback)
            distance = max(0.0, distance - 0.1)
            time.sleep(0.05)
        goal_handle.canceled()
        node.get_logger().info("goal canceled")
        return NavigateToPose.Result()

    serve_navigate_to_pose(node, execute)


if __name__ == "__main__":
    main()
