"""NotifyBase: report a broadcast survivor to the base station's report_survivor service."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from py_trees.common import Status

from sar_framework.engine.plugin import Param, leaf

from ._ros_leaf import RosLeaf
from ._service_call import PolledServiceCall

if TYPE_CHECKING:
    from .broadcast_survivor_tf import BroadcastSurvivorTF
    from .detect_survivor import DetectSurvivor


@leaf(
    params=[
        Param("detector", ref="DetectSurvivor",
              description="id of the DetectSurvivor leaf whose survivor location to report."),
        Param("broadcaster", ref="BroadcastSurvivorTF",
              description="id of the BroadcastSurvivorTF leaf whose survivor id to report."),
        Param("service_name", str, default="/report_survivor",
              description="Name of the sar_interfaces/srv/ReportSurvivor service."),
        Param("frame_id", str, default="map",
              description="Frame of the reported location."),
        Param("server_timeout_s", float, default=10.0, exclusive_minimum=0.0,
              description="Fail if the service is not ready within this many seconds."),
        Param("response_timeout_s", float, default=10.0, exclusive_minimum=0.0,
              description="Fail if the service has not answered this many seconds after "
                          "the request."),
    ],
)
class NotifyBase(RosLeaf):
    """Report the survivor to the ReportSurvivor service; SUCCESS only when acknowledged.

    The id is the child frame the referenced BroadcastSurvivorTF leaf allocated (its
    :meth:`survivor_id`), the location the referenced DetectSurvivor's survivor pose as a
    PointStamped in ``frame_id``. One request per activation, polled without blocking.
    FAILURE when there is nothing to report, when the report is not acknowledged, or when
    the service is not ready within ``server_timeout_s`` or silent for ``response_timeout_s``.

    Args:
        name: The behaviour's name.
        detector: The DetectSurvivor leaf (the location).
        broadcaster: The BroadcastSurvivorTF leaf (the survivor id).
        service_name: The ReportSurvivor service.
        frame_id: Frame of the reported location.
        server_timeout_s: Bound on waiting for the service.
        response_timeout_s: Bound on waiting for the answer.
    """

    def __init__(self, name: str, *, detector: DetectSurvivor, broadcaster: BroadcastSurvivorTF,
                 service_name: str = "/report_survivor", frame_id: str = "map",
                 server_timeout_s: float = 10.0, response_timeout_s: float = 10.0) -> None:
        super().__init__(name)
        self.detector = detector
        self.broadcaster = broadcaster
        self.service_name = service_name
        self.frame_id = frame_id
        self.server_timeout_s = server_timeout_s
        self.response_timeout_s = response_timeout_s
        self._call: PolledServiceCall | None = None
        self._srv_type: Any = None
        self._survivor_id: str | None = None
        self._pose: tuple[float, float] | None = None

    def setup(self, **kwargs: Any) -> None:
        """Take the ROS node and create the service client.

        Args:
            **kwargs: Must hold ``node``.
        """
        super().setup(**kwargs)
        from sar_interfaces.srv import ReportSurvivor

        self._srv_type = ReportSurvivor
        self._call = PolledServiceCall(
            self.node, ReportSurvivor, self.service_name,
            server_timeout_s=self.server_timeout_s, response_timeout_s=self.response_timeout_s,
        )

    def initialise(self) -> None:
        """Reset the latch; fix the survivor id and location this activation reports."""
        self._reset_latch()
        self._service().start()
        self._survivor_id = self.broadcaster.survivor_id()
        self._pose = self.detector.survivor_pose() if self.detector.was_found() else None
        if self._pose is None:
            self._latch(False, "no survivor detected to report")
        elif self._survivor_id is None:
            self._latch(False, "no survivor frame broadcast yet: nothing to report")

    def update(self) -> Status:
        """Poll the report.

        Returns:
            RUNNING until the answer; SUCCESS if acknowledged; FAILURE otherwise.
        """
        if self._done:
            return self._verdict()
        result = self._service().poll(self._request)
        if result is None:
            self.feedback_message = (f"waiting for {self.service_name}"
                                     if self._service().waiting_for_server()
                                     else f"reported {self._survivor_id}, awaiting acknowledgement")
            return Status.RUNNING
        if result.error is not None:
            return self._latch(False, result.error)
        assert self._pose is not None
        where = f"{self._survivor_id} at ({self._pose[0]:.2f}, {self._pose[1]:.2f})"
        if not result.response.acknowledged:
            return self._latch(False, f"report of {where} not acknowledged")
        return self._latch(True, f"Reported {where}: acknowledged.")

    def terminate(self, new_status: Status) -> None:
        """Drop a report still waiting for its answer when halted.

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

    def _request(self) -> Any:
        assert self._pose is not None and self._survivor_id is not None
        request = self._srv_type.Request()
        request.survivor_id = self._survivor_id
        request.location.header.frame_id = self.frame_id
        request.location.header.stamp = self.node.get_clock().now().to_msg()
        request.location.point.x, request.location.point.y = self._pose
        return request

    def _service(self) -> PolledServiceCall:
        if self._call is None:
            raise RuntimeError(f"NotifyBase '{self.name}' used before setup(node=...)")
        return self._call
