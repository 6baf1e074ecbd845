"""A minimal DetectSurvivor server for the environment smoke test.

Answers ``found=True`` at (1.5, -2.0) for ``zone_a`` and ``found=False`` otherwise, and
logs ``ready`` once the service exists.
"""

import rclpy
from _node_main import spin_until_interrupted
from rclpy.node import Node
from sar_interfaces.srv import DetectSurvivor


def main() -> None:
    """Serve until SIGINT."""
    rclpy.init()
    node = Node("detect_echo_server")

    def answer(request: DetectSurvivor.Request, response: DetectSurvivor.Response
               ) -> DetectSurvivor.Response:
        response.found = request.zone_id == "zone_a"
        if response.found:
            response.survivor_x, response.survivor_y = 1.5, -2.0
        node.get_logger().info(f"asked about {request.zone_id}")
        return response

    node.create_service(DetectSurvivor, "/detect_survivor", answer)
    node.get_logger().info("ready")
    spin_until_interrupted(node)


if __name__ == "__main__":
    main()
