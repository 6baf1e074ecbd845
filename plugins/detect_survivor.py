"""DetectSurvivor: ask the detect_survivor service about the current zone."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from py_trees.common import Status

from sar_framework.engine.plugin import Param, leaf

from ._ros_leaf import RosLeaf
from ._service_call import PolledServiceCall

if TYPE_CHECKING:
    from sar_framework.mission.zone_manager import ZoneManager


@leaf(
    params=[
        Param("service_name", str, default="/detect_survivor",
              description="Name of the sar_interfaces/srv/DetectSurvivor service."),
        Param("server_timeout_s", float, default=10.0, exclusive_minimum=0.0,
              description="Fail if the service is not ready within this many seconds."),
        Param("response_timeout_s", float, default=10.0, exclusive_minimum=0.0,
              description="Fail if the service has not answered this many seconds after "
                          "the request."),
    ],
    context=["zone_manager"],
)
class DetectSurvivor(RosLeaf):
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

    def __init__(self, name: str, *, zone_manager: ZoneManager,
                 service_name: str = "/detect_survivor", server_timeout_s: float = 10.0,
                 response_timeout_s: float = 10.0) -> None:
        super().__init__(name)
        self.zone_manager = zone_manager
        self.service_name = service_name
        self.server_timeout_s = server_timeout_s
        self.response_timeout_s = response_timeout_s
        self._call: PolledServiceCall | None = None
        self._srv_type: Any = None
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

    def setup(self, **kwargs: Any) -> None:
        """Take the ROS node and create the service client.

        Args:
            **kwargs: Must hold ``node``.
        """
        super().setup(**kwargs)
        from sar_interfaces.srv import DetectSurvivor as DetectSurvivorSrv

        self._srv_type = DetectSurvivorSrv
        self._call = PolledServiceCall(
            self.node, DetectSurvivorSrv, self.service_name,
            server_timeout_s=self.server_timeout_s, response_timeout_s=self.response_timeout_s,
        )

    def initialise(self) -> None:
        """Reset the latch and the previous result; pick the zone to ask about."""
        self._reset_latch()
        self._found = False
        self._pose = None
        self._service().start()
        try:
            self._zone_id = self.zone_manager.current_zone()["id"]
        except IndexError:
            self._zone_id = None
            self._latch(False, "no current zone to search: every zone has been visited")

    def update(self) -> Status:
        """Poll the request.

        Returns:
            RUNNING until the answer; SUCCESS with it; FAILURE on a bound or a failed call.
        """
        if self._done:
            return self._verdict()
        result = self._service().poll(lambda: self._srv_type.Request(zone_id=self._zone_id))
        if result is None:
            self.feedback_message = (f"waiting for {self.service_name}"
                                     if self._service().waiting_for_server()
                                     else f"asked {self.service_name} about {self._zone_id}")
            return Status.RUNNING
        if result.error is not None:
            return self._latch(False, result.error)
        response = result.response
        self._found = bool(response.found)
        if not self._found:
            return self._latch(True, f"{self._zone_id}: no survivor", log=False)
        self._pose = (float(response.survivor_x), float(response.survivor_y))
        return self._latch(True, f"{self._zone_id}: survivor found at "
                                 f"({self._pose[0]:.2f}, {self._pose[1]:.2f})", log=False)

    def terminate(self, new_status: Status) -> None:
        """Drop a request still waiting for its answer when halted.

        Args:
            new_status: The status the leaf is moving to.
        """
        if not self._done and self._call is not None:
            self._call.abandon()

    def shutdown(self) -> None:
        """Destroy the service client."""
        if self._call is not None:
            self._call.destroy()
            self._call = None

    def _service(self) -> PolledServiceCall:
        if self._call is None:
            raise RuntimeError(f"DetectSurvivor '{self.name}' used before setup(node=...)")
        return self._call
