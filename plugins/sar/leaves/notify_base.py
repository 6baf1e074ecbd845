"""NotifyBase: report a broadcast survivor to the base station's report_survivor service."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from py_trees.common import Status
from sar_plugins.sar.events import SarKind

from sar_framework.engine.plugin import Param, leaf
from sar_framework.leaves import ServiceLeaf, service_timeout_params

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
        *service_timeout_params(),
    ],
)
class NotifyBase(ServiceLeaf):
    """Report the survivor to the ReportSurvivor service; SUCCESS only when acknowledged.

    The id is the child frame the referenced BroadcastSurvivorTF leaf allocated (its
    :meth:`survivor_id`), the location the referenced DetectSurvivor's survivor pose as a
    PointStamped in ``frame_id``. One request per activation, polled without blocking.
    FAILURE when there is nothing to report, when the report is not acknowledged, or when
    the service is not ready within ``server_timeout_s`` or silent for ``response_timeout_s``;
    :meth:`failed_report` then says why, for a LogReportFailure leaf.

    Args:
        name: The behaviour's name.
        detector: The DetectSurvivor leaf (the location).
        broadcaster: The BroadcastSurvivorTF leaf (the survivor id).
        service_name: The ReportSurvivor service.
        frame_id: Frame of the reported location.
        server_timeout_s: Bound on waiting for the service.
        response_timeout_s: Bound on waiting for the answer.
    """

    service_type = "sar_interfaces/srv/ReportSurvivor"

    def __init__(self, name: str, *, detector: DetectSurvivor, broadcaster: BroadcastSurvivorTF,
                 service_name: str, frame_id: str, server_timeout_s: float,
                 response_timeout_s: float) -> None:
        super().__init__(name, detector=detector, broadcaster=broadcaster,
                         service_name=service_name, frame_id=frame_id,
                         server_timeout_s=server_timeout_s, response_timeout_s=response_timeout_s)
        self._survivor_id: str | None = None
        self._pose: tuple[float, float] | None = None
        self._failure: str | None = None

    def initialise(self) -> None:
        """Reset the latch; fix the survivor id and location this activation reports."""
        super().initialise()
        self._failure = None
        self._survivor_id = self.broadcaster.survivor_id()
        self._pose = self.detector.survivor_pose() if self.detector.was_found() else None
        if self._pose is None:
            self.latch(False, "no survivor detected to report")
        elif self._survivor_id is None:
            self.latch(False, "no survivor frame broadcast yet: nothing to report")

    def update(self) -> Status:
        """Poll the report; note why a report that was made failed.

        Returns:
            RUNNING until the answer, SUCCESS when acknowledged, FAILURE otherwise.
        """
        status = super().update()
        if status == Status.FAILURE and self._failure is None and self._pose is not None \
                and self._survivor_id is not None:
            self._failure = f"Report for {self._survivor_id} failed: {self.feedback_message}"
        return status

    def failed_report(self) -> str | None:
        """Say why the report of the detector's current survivor failed, if it did.

        Returns:
            ``Report for survivor_N refused by base: not acknowledged`` (or ``... failed:
            <reason>`` when the service did not answer); None when the report was
            acknowledged, is pending, or concerns an earlier detection.
        """
        current = self.detector.survivor_pose() if self.detector.was_found() else None
        if self.status != Status.FAILURE or current is None or current != self._pose:
            return None
        return self._failure

    def set_request(self, request: Any) -> None:
        """Report the survivor's id and location."""
        assert self._pose is not None and self._survivor_id is not None
        request.survivor_id = self._survivor_id
        request.location.header.frame_id = self.frame_id
        request.location.header.stamp = self.node.get_clock().now().to_msg()
        request.location.point.x, request.location.point.y = self._pose

    def waiting_message(self) -> str:
        """What the leaf says while the answer is due."""
        return f"reported {self._survivor_id}, awaiting acknowledgement"

    def on_response(self, response: Any) -> Status:
        """Judge the answer."""
        assert self._pose is not None
        where = f"{self._survivor_id} at ({self._pose[0]:.2f}, {self._pose[1]:.2f})"
        fields = {"source": self, "survivor_id": self._survivor_id or "",
                  "position": self._pose}
        if not response.acknowledged:
            reason = str(getattr(response, "reason", ""))  # the server's word, if it gave one
            why = reason or "not acknowledged"
            self._failure = f"Report for {self._survivor_id} refused by base: {why}"
            self.events.emit(SarKind.SURVIVOR_REFUSED, status="REFUSED", message=why,
                             **fields)
            return self.latch(False, f"report of {where} not acknowledged"
                                      + (f": {reason}" if reason else ""))
        self.events.emit(SarKind.SURVIVOR_REPORTED, status="ACKNOWLEDGED",
                         message=f"Report received: {where}. Acknowledged.", **fields)
        return self.latch(True, f"Reported {where}: acknowledged.")
