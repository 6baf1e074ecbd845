"""The simulated ``map_server``: a lifecycle node that latches ``/map`` when activated.

As Nav2's map_server: ``/map`` (``nav_msgs/OccupancyGrid``, RELIABLE, TRANSIENT_LOCAL,
depth 1) is published on activation, so late subscribers get it, and ``map_server/map``
(``nav_msgs/srv/GetMap``) answers with the same grid. ``map_server/load_map`` is not offered.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from nav_msgs.msg import OccupancyGrid as OccupancyGridMsg
from nav_msgs.srv import GetMap
from rclpy.lifecycle import LifecycleState, TransitionCallbackReturn

from sar_framework.ros.qos import latched_qos
from sar_framework.sim.lifecycle import Nav2LifecycleNode
from sar_framework.sim.messages import occupancy_grid_msg
from sar_framework.sim.occupancy import OccupancyGrid


class MapServer(Nav2LifecycleNode):
    """``map_server``.

    Args:
        grid: The map.
        frame_id: The map frame.
        now_ns: Simulated time (the map's stamp).
        yaml_filename: The map file (the ``yaml_filename`` parameter, as Nav2's).
    """

    def __init__(self, grid: OccupancyGrid, frame_id: str, now_ns: Callable[[], int],
                 yaml_filename: str) -> None:
        super().__init__("map_server")
        self._grid = grid
        self._frame = frame_id
        self._now_ns = now_ns
        self._msg: Any = None
        self.declare_parameter("yaml_filename", yaml_filename)
        self.declare_parameter("topic_name", "map")
        self.declare_parameter("frame_id", frame_id)
        self._publisher = self.create_lifecycle_publisher(
            OccupancyGridMsg, "map", latched_qos())
        self.create_service(GetMap, "~/map", self._on_get_map)

    def on_configure(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Build the map message."""
        self._msg = occupancy_grid_msg(self._grid, self._frame, self._now_ns())
        return super().on_configure(state)

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Activate the publisher and latch the map."""
        result = super().on_activate(state)
        self._publisher.publish(self._msg)
        return result

    def _on_get_map(self, _request: Any, response: Any) -> Any:
        if not self.active or self._msg is None:
            self.get_logger().warning("Received GetMap request but not in ACTIVE state, ignoring!")
            return response
        response.map = self._msg
        return response
