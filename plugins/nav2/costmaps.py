"""Nav2's costmap clearing nodes.

ClearEntireCostmap, ClearCostmapAroundRobot, ClearCostmapExceptRegion.

Service clients (:class:`~._bt_nodes.Nav2ServiceLeaf`) of a costmap's clearing service,
named by ``service_name`` as in Nav2's trees (``local_costmap/clear_entirely_local_costmap``).
"""

from __future__ import annotations

from sar_framework.engine.plugin import leaf
from sar_framework.engine.ports import InputPort

from ._bt_nodes import Nav2ServiceLeaf
from ._common import optional_input, timeout_port

_SERVICE = InputPort("service_name", str, optional=True,
                     description="Costmap service name responsible for clearing the costmap.")


@leaf(ports=[_SERVICE, timeout_port()])
class ClearEntireCostmap(Nav2ServiceLeaf):
    """Nav2's ClearEntireCostmap: clear every layer of a costmap."""

    service_type = "nav2_msgs/srv/ClearEntireCostmap"


def fill_reset_distance(leaf: Nav2ServiceLeaf) -> bool:
    """Fill a region-clearing request from the ``reset_distance`` port."""
    leaf.request.reset_distance = float(optional_input(leaf.ports, "reset_distance", 1.0))
    return True


@leaf(ports=[
    InputPort("reset_distance", float, default=1.0,
              description="Side size of the square area centered on the robot that will not "
                          "be cleared on the costmap (all the rest of the costmap will)."),
    _SERVICE, timeout_port(),
])
class ClearCostmapExceptRegion(Nav2ServiceLeaf):
    """Nav2's ClearCostmapExceptRegion: clear a costmap except a square around the robot."""

    service_type = "nav2_msgs/srv/ClearCostmapExceptRegion"

    def on_tick(self) -> bool:
        """Fill the request from the ports."""
        return fill_reset_distance(self)


@leaf(ports=[
    InputPort("reset_distance", float, default=1.0,
              description="Side size of the square area centered on the robot that will be "
                          "cleared on the costmap (the rest of the costmap won't)."),
    _SERVICE, timeout_port(),
])
class ClearCostmapAroundRobot(Nav2ServiceLeaf):
    """Nav2's ClearCostmapAroundRobot: clear a square of a costmap around the robot."""

    service_type = "nav2_msgs/srv/ClearCostmapAroundRobot"

    def on_tick(self) -> bool:
        """Fill the request from the ports."""
        return fill_reset_distance(self)
