"""``/detect_survivor``: answers whether a zone hides a survivor, from a table.

Parameters: :data:`~sar_plugins.sar.servers.params.DETECT_PARAMETERS` (``survivors_file``,
``service_name``, ``answer_delay_wall_s``); an empty ``survivors_file`` is the repository's
``config/survivors.yaml``, or the spec's table when that is absent.

Logs ``Detection request for zone_a: FOUND at (-2.50, 3.20)`` or
``Detection request for zone_b: no survivor`` per request, and ``ready: ...`` once serving.

Run: ``sar-detect-survivor-server`` or ``python -m sar_plugins.sar.servers.detect_survivor_server``
(``--ros-args -p survivors_file:=my_table.yaml``).
"""

from __future__ import annotations

import sys
import time
from collections.abc import Sequence

from rclpy.node import Node
from sar_interfaces.srv import DetectSurvivor
from sar_plugins.sar.servers.params import DETECT_PARAMETERS
from sar_plugins.sar.servers.survivors import default_survivors_source, load_survivors

from sar_framework.ros.parameters import declare_table
from sar_framework.ros.serve import serve

NODE_NAME = "detect_survivor_server"


class DetectSurvivorServer(Node):
    """Serves ``sar_interfaces/srv/DetectSurvivor`` from a survivor table.

    Raises:
        ValueError: The survivor table is malformed (``SurvivorsFileError``) or a parameter
            is invalid (``ParamsError``).
    """

    def __init__(self) -> None:
        super().__init__(NODE_NAME)
        values = declare_table(self, DETECT_PARAMETERS)
        file, service = values["survivors_file"], values["service_name"]
        self._delay_s = float(values["answer_delay_wall_s"])
        if file:
            self._table, source = load_survivors(file), file
        else:
            self._table, source = default_survivors_source()
        self._service = self.create_service(DetectSurvivor, service, self._answer)
        zones = ", ".join(sorted(self._table)) or "none"
        self.get_logger().info(
            f"ready: serving {service} with {len(self._table)} survivors ({zones}) from {source}"
        )

    def _answer(self, request: DetectSurvivor.Request,
                response: DetectSurvivor.Response) -> DetectSurvivor.Response:
        if self._delay_s:
            time.sleep(self._delay_s)
        position = self._table.get(request.zone_id)
        response.found = position is not None
        if position is None:
            self.get_logger().info(f"Detection request for {request.zone_id}: no survivor")
        else:
            response.survivor_x, response.survivor_y = position
            self.get_logger().info(
                f"Detection request for {request.zone_id}: "
                f"FOUND at ({position[0]:.2f}, {position[1]:.2f})"
            )
        return response


def main(argv: Sequence[str] | None = None) -> None:
    """Console entry point: serve until SIGINT (exit 0), or exit 2 on a bad table."""
    sys.exit(serve(DetectSurvivorServer, NODE_NAME, argv))


if __name__ == "__main__":
    main()
