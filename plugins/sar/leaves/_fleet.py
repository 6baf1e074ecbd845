"""What the fleet leaves share: the robot's name, the coordinator's names, finishing a zone.

The robot is its node's namespace (``/robot1`` -> ``robot1``); no leaf knows how many robots
there are. The coordinator's services and topics live under one absolute, fleet-wide name
(``/zone_coordinator``). Not a plugin itself (no ``@leaf`` mark); imports no ROS package.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from py_trees.common import Status

from sar_framework.engine.plugin import Param
from sar_framework.leaves import ServiceLeaf, service_timeout_params

if TYPE_CHECKING:
    from rclpy.node import Node
    from sar_plugins.sar.zone_manager import ZoneManager

COORDINATOR = "/zone_coordinator"

COORDINATOR_PARAM = Param("server_name", str, default=COORDINATOR,
                          description="The zone coordinator's name: its services and topics "
                                      "are under it (fleet-wide, absolute).")


def robot_name(node: Node) -> str:
    """The robot a runner's node stands for: its namespace without slashes.

    In the root namespace (one robot, no fleet) it is the node's name.
    """
    namespace = node.get_namespace().strip("/")
    return namespace.replace("/", "_") if namespace else node.get_name()


class FinishZoneLeaf(ServiceLeaf):
    """Tell the coordinator this robot is done with the current zone (one outcome).

    Args:
        name: The behaviour's name.
        zone_manager: The mission's shared zone state (its current zone is the claimed one).
        server_name: The coordinator's name.
        server_timeout_s: Bound on waiting for the service.
        response_timeout_s: Bound on waiting for the answer.
    """

    OUTCOME = 0
    VERB = "searched"

    service_type = "sar_fleet_interfaces/srv/FinishZone"

    def __init__(self, name: str, *, zone_manager: ZoneManager, server_name: str,
                 server_timeout_s: float, response_timeout_s: float) -> None:
        super().__init__(name, zone_manager=zone_manager,
                         service_name=f"{server_name.rstrip('/')}/finish_zone",
                         server_timeout_s=server_timeout_s, response_timeout_s=response_timeout_s)
        self._zone_id = ""

    def initialise(self) -> None:
        """Take the current zone, then start the request (FAILURE when there is none)."""
        super().initialise()
        try:
            self._zone_id = self.zone_manager.current_zone()["id"]
        except IndexError as err:
            self.latch(False, f"no zone to report: {err}")

    def set_request(self, request: Any) -> None:
        """Say which zone this robot finished, and how."""
        request.robot = robot_name(self.node)
        request.zone_id = self._zone_id
        request.outcome = self.OUTCOME

    def waiting_message(self) -> str:
        """What the leaf says while the answer is due."""
        return f"telling {self.service_name} that {self._zone_id} is {self.VERB}"

    def on_response(self, response: Any) -> Status:
        """Judge the answer."""
        if response.accepted:
            return self.latch(True, f"{self._zone_id} {self.VERB} (coordinator told)")
        return self.latch(False, f"the coordinator refused {self._zone_id} "
                                  f"{self.VERB}: {response.reason}")


FINISH_PARAMS: tuple[Param, ...] = (COORDINATOR_PARAM, *service_timeout_params())
"""The params CompleteZone and ReleaseZone declare."""
