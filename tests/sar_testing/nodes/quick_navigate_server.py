"""A NavigateToPose server that reaches every goal after a short drive.

Each goal succeeds after ``--drive-s`` seconds (default 0.3) unless cancelled. Logs
``ready`` once serving and ``goal x=.. y=.. frame=..`` per accepted goal.
"""

import argparse
import time

import rclpy
from _node_main import serve_navigate_to_pose
from nav2_msgs.action import NavigateToPose
from rclpy.node import Node


def main() -> None:
    """Serve until SIGINT."""
    parser = argparse.ArgumentParser()
    parser.add_argument("--drive-s", type=float, default=0.3)
    options, ros_args = parser.parse_known_args()
    rclpy.init(args=ros_args)
    node = Node("quick_navigate_server")

    def execute(goal_handle):
        pose = goal_handle.request.pose
        node.get_logger().info(f"goal x={pose.pose.position.x:.2f} y={pose.pose.position.y:.2f} "
                               f"frame={pose.header.frame_id}")
        for _ in range(round(options.drive_s / 0.02)):  # drives at least drive_s
            if goal_handle.is_cancel_requested:
                goal_handle.canceled()
                return NavigateToPose.Result()
            time.sleep(0.02)
        goal_handle.succeed()
        return NavigateToPose.Result()

    serve_navigate_to_pose(node, execute)


if __name__ == "__main__":
    main()
