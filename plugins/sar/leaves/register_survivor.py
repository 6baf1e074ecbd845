"""RegisterSurvivor: ask the fleet's survivor registry for the survivor's id and who reports it."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from py_trees.common import Status

from sar_framework.engine.plugin import Param, leaf
from sar_framework.events.event import EventKind
from sar_framework.leaves import ServiceLeaf, service_timeout_params

if TYPE_CHECKING:
    from .detect_survivor import DetectSurvivor


@leaf(
    params=[
        Param("detector", ref="DetectSurvivor",
              description="id of the DetectSurvivor leaf whose survivor to register."),
        Param("service_name", str, default="/zone_coordinator/register_survivor",
              description="Name of the sar_fleet_interfaces/srv/RegisterSurvivor service (the "
                          "fleet's one registry, hosted by the zone coordinator)."),
        *service_timeout_params(),
    ],
)
class RegisterSurvivor(ServiceLeaf):
    """Register the detected survivor with the fleet; SUCCESS when this robot reports it.

    The robot is the runner node's namespace without its leading ``/`` (``/robot1`` ->
    ``robot1``; the node's name in the root namespace). The registry answers with the
    survivor's fleet-wide id (the same for every robot that finds it within the registry's
    radius) and whether this robot broadcasts and reports it. SUCCESS when it does: the id
    is then readable through :meth:`survivor_id`, which a BroadcastSurvivorTF leaf with
    ``registrar`` set uses instead of allocating one. FAILURE, with a ``note`` event, when
    another robot already has it (:meth:`duplicate`); FAILURE too when there is no survivor,
    the registry refuses the request, or does not answer within the bounds
    (:meth:`failed_registration`). A LogSurvivorNotRegistered leaf after the branch turns
    both into SUCCESS, so a duplicate never reads as "no survivor found".

    Args:
        name: The behaviour's name.
        detector: The DetectSurvivor leaf (the location and zone).
        service_name: The RegisterSurvivor service.
        server_timeout_s: Bound on waiting for the service.
        response_timeout_s: Bound on waiting for the answer.
    """

    service_type = "sar_fleet_interfaces/srv/RegisterSurvivor"

    def __init__(self, name: str, *, detector: DetectSurvivor, service_name: str,
                 server_timeout_s: float, response_timeout_s: float) -> None:
        super().__init__(name, detector=detector, service_name=service_name,
                         server_timeout_s=server_timeout_s, response_timeout_s=response_timeout_s)
        self.robot = ""
        self._pose: tuple[float, float] | None = None
        self._zone_id = ""
        self._survivor_id: str | None = None
        self._duplicate: str | None = None
        self._failure: str | None = None

    def setup(self, **kwargs: Any) -> None:
        """Take the ROS node, name the robot after its namespace, create the client.

        Args:
            **kwargs: Must hold ``node``.
        """
        super().setup(**kwargs)
        self.robot = self.node.get_namespace().strip("/") or self.node.get_name()

    def survivor_id(self) -> str | None:
        """The fleet id this robot broadcasts and reports, or None (not its to report)."""
        return self._survivor_id

    def duplicate(self) -> str | None:
        """Why the current survivor is not this robot's to report, or None."""
        return self._duplicate if self._is_current() else None

    def failed_registration(self) -> str | None:
        """Why the current detection could not be registered, or None."""
        return self._failure if self._is_current() else None

    def initialise(self) -> None:
        """Reset the latch; fix the location and zone this activation registers."""
        super().initialise()
        self._survivor_id = self._duplicate = self._failure = None
        self._pose = self.detector.survivor_pose() if self.detector.was_found() else None
        self._zone_id = self.detector.zone_id() or ""
        if self._pose is None:
            self.latch(False, "no survivor detected to register")

    def update(self) -> Status:
        """Poll the registration; note why one that was asked for failed.

        Returns:
            RUNNING until the answer, SUCCESS when this robot reports the survivor, FAILURE
            otherwise.
        """
        status = super().update()
        if status == Status.FAILURE and self._pose is not None and self._duplicate is None \
                and self._failure is None:
            self._failure = f"Survivor at {self._where()} not registered: {self.feedback_message}"
        return status

    def _is_current(self) -> bool:
        current = self.detector.survivor_pose() if self.detector.was_found() else None
        return self.status == Status.FAILURE and current is not None and current == self._pose

    def _where(self) -> str:
        assert self._pose is not None
        return f"({self._pose[0]:.2f}, {self._pose[1]:.2f})"

    def set_request(self, request: Any) -> None:
        """Register the detected location for this robot."""
        assert self._pose is not None
        request.robot, request.zone_id = self.robot, self._zone_id
        request.x, request.y = self._pose

    def waiting_message(self) -> str:
        """What the leaf says while the answer is due."""
        return f"registered the survivor at {self._where()}, awaiting its fleet id"

    def on_response(self, response: Any) -> Status:
        """Judge the answer."""
        if not response.survivor_id:
            why = response.reason or "no id given"
            self._failure = f"Survivor at {self._where()} not registered: {why}"
            return self.latch(False, self._failure)
        if response.report:
            self._survivor_id = response.survivor_id
            return self.latch(True, f"Registered the survivor at {self._where()} as "
                                     f"{response.survivor_id}: {self.robot} reports it.")
        self._duplicate = (f"Survivor at {self._where()} is {response.survivor_id}, found by "
                           f"{response.found_by}: not reported again ({response.reason}).")
        self.events.emit(EventKind.NOTE, source=self, message=self._duplicate,
                         zone_id=self._zone_id, survivor_id=response.survivor_id,
                         position=self._pose)
        return self.latch(False, self._duplicate)
