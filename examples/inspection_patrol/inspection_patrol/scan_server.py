"""The inspection patrol's scan server: ``python -m inspection_patrol.scan_server``.

A program of its own, which the app's process description starts beside the runner for a
tree that uses the app. It offers one ``std_srvs/srv/Trigger`` service per shelf it knows
(``scan_shelf/A``, ``scan_shelf/B``...; parameter ``shelves``, which the app sets from
its shelves' data file), so the request needs no
fields: the service's name says which shelf to scan. Nothing here runs on import (the
tree's ``plugins:`` imports every file of the folder).
"""

from __future__ import annotations

import sys
from collections.abc import Sequence
from typing import Any

NODE_NAME = "shelf_scanner"
SERVICE = "scan_shelf"
"""The services' common prefix: ``scan_shelf/<shelf>``."""


def make_node() -> Any:
    """The scan server's node: a Trigger service per shelf, each answering ``shelf X scanned``."""
    from rclpy.node import Node
    from rclpy.parameter import Parameter
    from std_srvs.srv import Trigger

    node = Node(NODE_NAME)
    shelves = node.declare_parameter("shelves", Parameter.Type.STRING_ARRAY).value
    if not shelves or not all(isinstance(s, str) and s.isidentifier() for s in shelves):
        raise ValueError(f"parameter 'shelves': a list of names is needed, got {shelves!r}")

    def scanner(shelf: str) -> Any:
        def scan(_request: Any, response: Any) -> Any:
            response.success = True
            response.message = f"shelf {shelf} scanned"
            return response
        return scan

    for shelf in shelves:  # the node keeps its services
        node.create_service(Trigger, f"{SERVICE}/{shelf}", scanner(shelf))
    node.get_logger().info(f"scanning shelves {', '.join(shelves)}")
    return node


def main(argv: Sequence[str] | None = None) -> None:
    """Serve until SIGINT (exit 0), or exit 2 on bad parameters."""
    from sar_framework.ros.serve import serve

    sys.exit(serve(make_node, NODE_NAME, argv))


if __name__ == "__main__":
    main()
