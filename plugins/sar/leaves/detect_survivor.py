"""DetectSurvivor: ask the detect_survivor service about the current zone."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from py_trees.common import Status
from sar_plugins.sar.events import SarKind

from sar_framework.engine.plugin import Param, leaf
from sar_framework.leaves import ServiceLeaf, service_timeout_params

if TYPE_CHECKING:
    from sar_plugins.sar.zone_manager import ZoneManager


@leaf(
    params=[
        Param("service_name", str, default="detect_survivor",
              description="Name of the sar_interfaces/srv/DetectSurvivor service."),
        *service_timeout_params(),
    ],
    context=["zone_manager"],
)
class DetectSurvivor(ServiceLeaf):
    """Ask the DetectSurvivor service whether the current zone holds a survivor.

    One request per activation, polled without blocking (RUNNING until the answer).
    SUCCESS whether or not a survivor was found; the result is kept for the leaves that
    reference this one (IsSurvivorDetected, BroadcastSurvivorTF, NotifyBase) through
    :meth:`was_found` and :meth:`survivor_pose`. FAILURE when the service is not ready within
    ``server_timeout_s`` or does not answer within ``response_timeout_s``.

    Args:
        name: The behaviour's name.
        zone_manager: The mission's shared zone state.
        service_name: The DetectSurvivor service.
        server_timeout_s: Bound on waiting for the service.
        response_timeout_s: Bound on waiting for the answer.
    """

    service_type = "sar_interfaces/srv/DetectSurvivor"

    def __init__(self, name: str, *, zone_manager: ZoneManager, service_name: str,
                 server_timeout_s: float, response_timeout_s: float) -> None:
        super().__init__(name, zone_manager=zone_manager, service_name=service_name,
                         server_timeout_s=server_timeout_s, response_timeout_s=response_timeout_s)
        self._zone_id: str | None = None
        self._found = False
        self._pose: tuple[float, float] | None = None

    def was_found(self) -> bool:
        """Whether the last completed request found a survivor (False while one is running)."""
        return self._found

    def survivor_pose(self) -> tuple[float, float] | None:
        """The ``(x, y)`` of the survivor found by the last request (frame ``map``), or None."""
        return self._pose

    def zone_id(self) -> str | None:
        """The zone the last request asked about, or None."""
        return self._zone_id

    def initialise(self) -> None:
        """Reset the latch and the previous result; pick the zone to ask about."""
        self._found = False
        self._pose = None
        super().initialise()
        try:
            self._zone_id = self.zone_manager.current_zone()["id"]
        except IndexError:
            self._zone_id = None
            self.latch(False, "no current zone to search: every zone has been visited")

    def set_request(self, request: Any) -> None:
        """Ask about the current zone."""
        request.zone_id = self._zone_id

    def waiting_message(self) -> str:
        """What the leaf says while the answer is due."""
        return f"asked {self.service_name} about {self._zone_id}"

    def on_response(self, response: Any) -> Status:
        """Judge the answer."""
        self._found = bool(response.found)
        if self._found:
            self._pose = (float(response.survivor_x), float(response.survivor_y))
            message = (f"{self._zone_id}: survivor found at "
                       f"({self._pose[0]:.2f}, {self._pose[1]:.2f})")
        else:
            message = f"{self._zone_id}: no survivor"
        said = (f"FOUND at ({self._pose[0]:.2f}, {self._pose[1]:.2f})" if self._pose
                else "no survivor")
        self.events.emit(SarKind.DETECTION, source=self, zone_id=self._zone_id or "",
                         status="FOUND" if self._found else "NONE",
                         message=f"Detection request for {self._zone_id}: {said}",
                         position=self._pose)
        return self.latch(True, message, log=False)
