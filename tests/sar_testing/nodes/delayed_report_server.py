"""A ReportSurvivor server that answers after a delay, for the SurvivorFound branch tests.

``--delay`` seconds after each request it answers ``acknowledged=True`` (``--refuse``:
False), without blocking other requests. Logs ``ready`` and, per request,
``report: survivor_1 at (-2.50, 3.20) frame=map``.
"""

import argparse
import time

import rclpy
from _node_main import spin_until_interrupted
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.node import Node
from sar_interfaces.srv import ReportSurvivor


def main() -> None:
    """Serve until SIGINT."""
    parser = argparse.ArgumentParser()
    parser.add_argument("--delay", type=float, default=1.0)
    parser.add_argument("--refuse", action="store_true")
    args = parser.parse_args()
    rclpy.init()
    node = Node("delayed_report_server")

    def answer(request: ReportSurvivor.Request, response: ReportSurvivor.Response
               ) -> ReportSurvivor.Response:
        point = request.location.point
        node.get_logger().info(f"report: {request.survivor_id} at ({point.x:.2f}, {point.y:.2f}) "
                               f"frame={request.location.header.frame_id}")
        time.sleep(args.delay)
        response.acknowledged = not args.refuse
        return response

    node.create_service(ReportSurvivor, "/report_survivor", answer,
                        callback_group=ReentrantCallbackGroup())
    node.get_logger().info("ready")
    spin_until_interrupted(node, threads=4)


if __name__ == "__main__":
    main()
