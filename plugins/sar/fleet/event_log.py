"""The zone coordinator's events: ``FleetEvent`` messages and their JSON Lines copy.

Each event goes on ``/zone_coordinator/events`` (RELIABLE, TRANSIENT_LOCAL, keep last 1000)
and, when an ``events_file`` is set, as one JSON object per line, flushed at once::

    {"seq": 3, "wall_s": 1.52, "stamp": 12.5, "kind": "bid", "auction_id": 1,
     "robot": "robot1", "zone_id": "", "zone_ids": ["zone_a", "zone_b"], "robots": [],
     "costs": [4.2, null], "survivor_id": "", "position": null, "message": "..."}

A cost the robot cannot reach (``inf`` in the message) is ``null`` in JSON, which has no
infinity; ``position`` is ``[x, y, z]`` or ``null``.
"""

from __future__ import annotations

import json
import math
import time
from collections.abc import Sequence
from typing import IO, TYPE_CHECKING, Any

from sar_fleet_interfaces.msg import FleetEvent

from sar_framework.ros.qos import latched_qos

if TYPE_CHECKING:
    from rclpy.node import Node

EVENTS_TOPIC = "/zone_coordinator/events"
EVENTS_DEPTH = 1000


class FleetEventLog:
    """Publishes the coordinator's events and appends them to its events file.

    Args:
        node: The coordinator's node.
        events_file: JSON Lines file ('' = none); truncated when opened.

    Raises:
        OSError: The file cannot be opened.
    """

    def __init__(self, node: Node, events_file: str) -> None:
        self._node = node
        self._publisher = node.create_publisher(FleetEvent, EVENTS_TOPIC,
                                                latched_qos(EVENTS_DEPTH))
        self._file: IO[str] | None = open(events_file, "w", encoding="utf-8") \
            if events_file else None  # noqa: SIM115 (kept open for the node's life)
        self._seq = 0
        self._wall_start = time.monotonic()

    def emit(self, kind: str, message: str, *, auction_id: int = 0, robot: str = "",
             zone_id: str = "", zone_ids: Sequence[str] = (), robots: Sequence[str] = (),
             costs: Sequence[float] = (), survivor_id: str = "",
             position: tuple[float, float, float] | None = None) -> FleetEvent:
        """Publish one event (and write its line); return the message.

        Args:
            kind: One of ``FleetEvent.KIND_*``.
            message: One line for humans (also logged).
            auction_id: The round it concerns (0: none).
            robot: The robot it concerns.
            zone_id: The zone it concerns.
            zone_ids: The zones (auction, bid, robot_lost).
            robots: The bidders (auction).
            costs: One per zone (bid) or the award's cost.
            survivor_id: The survivor it concerns.
            position: Metres in the map frame, when known.
        """
        self._seq += 1
        event = FleetEvent()
        event.stamp = self._node.get_clock().now().to_msg()
        event.wall_s = time.monotonic() - self._wall_start
        event.seq = self._seq
        event.kind = kind
        event.auction_id = auction_id
        event.robot = robot
        event.zone_id = zone_id
        event.zone_ids = list(zone_ids)
        event.robots = list(robots)
        event.costs = [float(c) for c in costs]
        event.survivor_id = survivor_id
        event.has_position = position is not None
        if position is not None:
            event.position.x, event.position.y, event.position.z = position
        event.message = message
        self._publisher.publish(event)
        self._node.get_logger().info(message)
        if self._file is not None:
            self._file.write(json.dumps(_record(event)) + "\n")
            self._file.flush()
        return event

    def close(self) -> None:
        """Close the events file."""
        if self._file is not None:
            self._file.close()
            self._file = None


def _record(event: FleetEvent) -> dict[str, Any]:
    position = event.position
    return {
        "seq": event.seq, "wall_s": round(event.wall_s, 4),
        "stamp": event.stamp.sec + event.stamp.nanosec * 1e-9, "kind": event.kind,
        "auction_id": event.auction_id, "robot": event.robot, "zone_id": event.zone_id,
        "zone_ids": list(event.zone_ids), "robots": list(event.robots),
        "costs": [c if math.isfinite(c) else None for c in event.costs],
        "survivor_id": event.survivor_id,
        "position": [position.x, position.y, position.z] if event.has_position else None,
        "message": event.message,
    }
