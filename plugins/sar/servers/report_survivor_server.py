"""``/report_survivor``: validates survivor reports and records each one durably.

A report is refused (``acknowledged=False``, ``reason`` saying why, and a warning in the
log) when its frame is not the global frame (``map``), a coordinate is not finite, or the
survivor id is empty, longer than 64 characters or holds control characters. An accepted
report is appended to a JSON Lines file and fsync-ed *before* the answer leaves, so
nothing acknowledged is lost;
a survivor id reported again is acknowledged again but not written twice (ids already in
the file count too, so this holds across restarts).

Parameters: :data:`~sar_plugins.sar.servers.params.REPORT_PARAMETERS` (``report_file``,
``service_name``, ``global_frame``, ``refuse_all``, ``answer_delay_wall_s``).

Logs ``Report received: survivor_1 at (-2.50, 3.20). Acknowledged.`` per new report and
``ready: ...`` once serving.
"""

from __future__ import annotations

import math
import os
import sys
import time
from collections.abc import Sequence
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

from rclpy.node import Node
from sar_interfaces.srv import ReportSurvivor
from sar_plugins.sar.servers.params import REPORT_PARAMETERS
from sar_plugins.sar.servers.report_log import ReportLog

from sar_framework.ros.parameters import declare_table
from sar_framework.ros.serve import ServerConfigError, serve

NODE_NAME = "report_survivor_server"
#: Longest survivor id accepted.
MAX_ID_LENGTH = 64


def default_report_file() -> Path:
    """Return ``$ROS_HOME/sar_reports.jsonl`` (``~/.ros`` when ROS_HOME is unset)."""
    home = os.environ.get("ROS_HOME") or os.path.join(os.path.expanduser("~"), ".ros")
    return Path(home) / "sar_reports.jsonl"


def check_report(request: ReportSurvivor.Request, global_frame: str) -> str | None:
    """Return why a report must be refused, or None when it is acceptable.

    Args:
        request: The service request.
        global_frame: The frame the location must be expressed in.
    """
    survivor_id = request.survivor_id
    if not survivor_id:
        return "empty survivor id"
    if len(survivor_id) > MAX_ID_LENGTH:
        return f"survivor id is {len(survivor_id)} characters long (at most {MAX_ID_LENGTH})"
    if not survivor_id.isprintable():
        return f"survivor id {survivor_id!r} holds control characters"
    frame = request.location.header.frame_id
    if frame != global_frame:
        return f"location frame is {frame!r}, expected {global_frame!r}"
    point = request.location.point
    if not all(math.isfinite(v) for v in (point.x, point.y, point.z)):
        return f"location is not finite: ({point.x}, {point.y}, {point.z})"
    return None


class ReportSurvivorServer(Node):
    """Serves ``sar_interfaces/srv/ReportSurvivor`` and records acknowledged reports.

    Raises:
        ServerConfigError: The report file cannot be opened or a parameter is invalid.
    """

    def __init__(self) -> None:
        super().__init__(NODE_NAME)
        values = declare_table(self, REPORT_PARAMETERS)
        file = values["report_file"] or str(default_report_file())
        service = values["service_name"]
        self._frame = values["global_frame"]
        self._refuse_all = values["refuse_all"]
        self._delay_s = float(values["answer_delay_wall_s"])
        self._log = ReportLog(file)
        try:
            opened = self._log.open()
        except OSError as err:
            raise ServerConfigError(f"report_file: cannot open {file}: {err}") from None
        if opened.unreadable_lines:
            lines = ", ".join(str(n) for n in opened.unreadable_lines)
            self.get_logger().warning(f"{file}: skipped unreadable line(s) {lines}")
        self._service = self.create_service(ReportSurvivor, service, self._answer)
        extra = " (refusing every report: refuse_all is set)" if self._refuse_all else ""
        self.get_logger().info(
            f"ready: serving {service}, recording to {file} "
            f"({opened.loaded} survivors already on record){extra}"
        )

    def _answer(self, request: ReportSurvivor.Request,
                response: ReportSurvivor.Response) -> ReportSurvivor.Response:
        if self._delay_s:
            time.sleep(self._delay_s)
        response.acknowledged = False
        point = request.location.point
        where = f"({point.x:.2f}, {point.y:.2f})"
        if self._refuse_all:
            response.reason = "refuse_all is set"
            self.get_logger().warning(
                f"Report refused: {request.survivor_id!r} at {where}: {response.reason}")
            return response
        reason = check_report(request, self._frame)
        if reason is not None:
            response.reason = reason
            self.get_logger().warning(
                f"Report refused: {request.survivor_id[:80]!r} at {where}: {reason}")
            return response
        survivor_id = request.survivor_id
        known = self._log.get(survivor_id)
        if known is not None:
            moved = not (math.isclose(known.get("x", math.nan), point.x, abs_tol=1e-6)
                         and math.isclose(known.get("y", math.nan), point.y, abs_tol=1e-6))
            note = (f"; it differs from the recorded ({known.get('x')}, {known.get('y')}),"
                    " which is kept") if moved else ""
            self.get_logger().info(
                f"Repeated report: {survivor_id} at {where}. Acknowledged; already on record{note}."
            )
            response.acknowledged = True
            return response
        try:
            self._log.append(self._record(request))
        except OSError as err:
            response.reason = f"cannot record {survivor_id}: {err}"
            self.get_logger().error(f"Report refused: {response.reason}")
            return response
        self.get_logger().info(f"Report received: {survivor_id} at {where}. Acknowledged.")
        response.acknowledged = True
        return response

    def _record(self, request: ReportSurvivor.Request) -> dict[str, Any]:
        stamp = request.location.header.stamp
        point = request.location.point
        return {
            "survivor_id": request.survivor_id,
            "frame_id": request.location.header.frame_id,
            "x": point.x,
            "y": point.y,
            "z": point.z,
            "stamp": stamp.sec + stamp.nanosec * 1e-9,
            "received_at": datetime.now(timezone.utc).isoformat(timespec="milliseconds"),
        }

    def destroy_node(self) -> None:
        """Close the report file, then destroy the node."""
        self._log.close()
        super().destroy_node()


def main(argv: Sequence[str] | None = None) -> None:
    """Console entry point: serve until SIGINT (exit 0), or exit 2 on a bad configuration."""
    sys.exit(serve(ReportSurvivorServer, NODE_NAME, argv))


if __name__ == "__main__":
    main()
