"""The survivor registry as a ROS service on the zone coordinator's node.

:class:`SurvivorRegistryService` attaches ``sar_fleet_interfaces/srv/RegisterSurvivor`` at
``/zone_coordinator/register_survivor`` to a node it is given (the zone coordinator
constructs it with its ``survivor_radius_m``)::

    survivors = SurvivorRegistryService(node, radius_m=1.0, on_registered=emit_event)
    ...
    survivors.robot_lost("robot2")        # when the coordinator declares robot2 lost

A request the registry refuses (an empty robot name, a coordinate that is not finite) is
answered with an empty ``survivor_id``, ``report=False`` and the reason, and logged as a
warning; nothing is registered. Every accepted registration is handed to ``on_registered``
(for the coordinator's ``survivor_registered`` FleetEvent; :func:`fill_fleet_event` fills
one) after the registry has answered it.

The registry is guarded by a lock, so a multi-threaded executor may run the service and
the coordinator's liveness timer at once.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from sar_plugins.sar.fleet.survivor_registry import (
    Registration,
    RegistrationError,
    SurvivorRegistry,
)

if TYPE_CHECKING:
    from rclpy.node import Node

#: The fleet-wide service name (absolute: one registry serves every robot's namespace).
REGISTER_SURVIVOR_SERVICE = "/zone_coordinator/register_survivor"
#: The FleetEvent kind of an accepted registration.
SURVIVOR_REGISTERED = "survivor_registered"

RegistrationListener = Callable[[Registration], None]
"""Told every accepted registration, in order (the coordinator's event emitter)."""


class SurvivorRegistryService:
    """Serves the fleet's survivor registry on a node.

    Args:
        node: The rclpy node to attach the service to (the zone coordinator's).
        radius_m: Survivors registered within this distance are one (finite, positive).
        on_registered: Called with every accepted :class:`Registration`.
        service_name: Where to serve; the fleet-wide name unless testing.

    Raises:
        ValueError: ``radius_m`` is not a finite positive number.
    """

    def __init__(self, node: Node, radius_m: float, *,
                 on_registered: RegistrationListener | None = None,
                 service_name: str = REGISTER_SURVIVOR_SERVICE) -> None:
        from sar_fleet_interfaces.srv import RegisterSurvivor

        self._node = node
        self._registry = SurvivorRegistry(radius_m)
        self._lock = threading.Lock()
        self._on_registered = on_registered
        self.service_name = service_name
        self._service: Any = node.create_service(RegisterSurvivor, service_name, self._answer)

    def robot_lost(self, robot: str) -> tuple[str, ...]:
        """Tell the registry the fleet declared ``robot`` lost.

        Its survivors not known as reported go to the next robot that registers them.

        Args:
            robot: The lost robot's name.

        Returns:
            The ids handed back (for the coordinator's ``robot_lost`` event).
        """
        with self._lock:
            handed_back = self._registry.robot_lost(robot)
        if handed_back:
            self._node.get_logger().info(
                f"{robot} lost: the next finder of {', '.join(handed_back)} reports it")
        return handed_back

    def survivor_reported(self, survivor_id: str) -> None:
        """Tell the registry the base acknowledged ``survivor_id``'s report.

        Args:
            survivor_id: A registered survivor's id.

        Raises:
            KeyError: No survivor has this id.
        """
        with self._lock:
            self._registry.mark_reported(survivor_id)

    def survivor_ids(self) -> tuple[str, ...]:
        """Every registered survivor's id, in registration order."""
        with self._lock:
            return self._registry.survivor_ids()

    def destroy(self) -> None:
        """Remove the service from the node."""
        if self._service is not None:
            self._node.destroy_service(self._service)
            self._service = None

    def _answer(self, request: Any, response: Any) -> Any:
        try:
            with self._lock:
                registration = self._registry.register(request.robot, request.x, request.y,
                                                       request.zone_id)
        except RegistrationError as err:
            response.survivor_id = ""
            response.report = False
            response.found_by = ""
            response.reason = f"registration refused: {err}"
            self._node.get_logger().warning(
                f"Survivor registration from {request.robot[:80]!r} refused: {err}")
            return response
        response.survivor_id = registration.survivor_id
        response.report = registration.report
        response.found_by = registration.found_by
        response.reason = registration.reason
        self._node.get_logger().info(registration.describe())
        if self._on_registered is not None:
            self._on_registered(registration)
        return response
