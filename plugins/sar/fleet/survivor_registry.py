"""The fleet's survivor registry: one fleet-wide id per survivor, one robot to report it (no ROS).

Every robot that finds a survivor registers it with the fleet (the zone coordinator hosts
the registry, :mod:`sar_plugins.sar.fleet.survivor_service`). A survivor registered within
``radius_m`` of one already known is the same survivor and gets the same id; otherwise it
gets the next id, ``survivor_1``, ``survivor_2``... counted fleet-wide, in registration order.

Who reports (broadcasts the TF frame and calls the base's ``/report_survivor``): the
survivor's *reporter*. The first robot to register it becomes its reporter and is told
``report=True``; a later finder gets the same id with ``report=False``, ``found_by`` (the
first finder) and a reason. Nothing reported is lost when a robot is:

* :meth:`SurvivorRegistry.robot_lost` hands back every survivor the lost robot was to
  report and that is not known as reported; the next robot to register it becomes its
  reporter (``report=True``, a *takeover*);
* :meth:`SurvivorRegistry.mark_reported` says the base acknowledged a survivor; after it,
  a lost reporter hands nothing back.

When the registry is never told of acknowledgements, a lost reporter's survivors are always
handed back, so a survivor its reporter did report may be reported again by the next
finder. That is sound because the ids are fleet-wide and the base records a survivor id
once (a repeated report is acknowledged, not written again: ``report_survivor_server``):
erring towards a second report never loses one and never counts one twice.

A reporter registering its own survivor again (a request sent again, a retried branch)
is told ``report=True`` again, even once reported: the answer is the same for the same
question, and the base records an id once.

Matching uses the position first registered for each survivor (positions never move, so
chains of nearby finds cannot drift); with several known survivors within the radius, the
nearest wins. Survivors closer than ``radius_m`` to each other are, by this rule, one.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

#: The prefix of every fleet-wide survivor id.
ID_PREFIX = "survivor_"


class RegistrationError(ValueError):
    """A registration the registry refuses (bad robot name or position); says which field."""


@dataclass(frozen=True)
class Registration:
    """The registry's answer to one registration.

    Attributes:
        survivor_id: The fleet-wide id, ``survivor_N``.
        robot: The robot that registered.
        zone_id: The zone it said it searched ('' when it did not say).
        x: Where it found the survivor (metres, map frame).
        y: Where it found the survivor.
        report: Whether this robot should broadcast and report it.
        found_by: The robot that registered the survivor first.
        reason: Why not to report ('' when ``report`` is True).
        first: Whether this registration created the survivor.
        takeover: Whether this robot became the reporter of a lost robot's survivor.
    """

    survivor_id: str
    robot: str
    zone_id: str
    x: float
    y: float
    report: bool
    found_by: str
    reason: str
    first: bool
    takeover: bool = False

    def describe(self) -> str:
        """One line for humans, e.g. ``robot2 found survivor_1 at (1.50, -2.00): repeat, ...``."""
        where = f"{self.robot} found {self.survivor_id} at ({self.x:.2f}, {self.y:.2f})"
        if self.first:
            return f"{where}: first, it reports it"
        if self.takeover:
            return f"{where}: repeat, it reports it (its reporter was lost)"
        if self.report:
            return f"{where}: again, it reports it"
        return f"{where}: repeat, not reported again ({self.reason})"


@dataclass
class _Survivor:
    """One known survivor."""

    survivor_id: str
    x: float
    y: float
    found_by: str
    reporter: str | None  # None: handed back by a lost reporter, the next finder reports
    reported_by: str | None = None
    finders: set[str] = field(default_factory=set)


class SurvivorRegistry:
    """Fleet-wide survivor ids by radius, and which robot reports each survivor.

    Args:
        radius_m: Survivors registered within this distance (metres) are one; finite and
            positive.

    Raises:
        ValueError: ``radius_m`` is not a finite positive number.
    """

    def __init__(self, radius_m: float) -> None:
        if isinstance(radius_m, bool) or not isinstance(radius_m, (int, float)) \
                or not math.isfinite(radius_m) or radius_m <= 0.0:
            raise ValueError(f"radius_m must be a finite positive number of metres, "
                             f"got {radius_m!r}")
        self.radius_m = float(radius_m)
        self._survivors: list[_Survivor] = []

    def register(self, robot: str, x: float, y: float, zone_id: str = "") -> Registration:
        """Register a survivor ``robot`` found at ``(x, y)``.

        Args:
            robot: The finder's name (its namespace without the leading ``/``).
            x: Metres in the map frame.
            y: Metres in the map frame.
            zone_id: The zone it searched, for the record.

        Returns:
            The survivor's id and whether ``robot`` reports it.

        Raises:
            RegistrationError: ``robot`` is empty or holds whitespace or control characters,
                or a coordinate is not a finite number.
        """
        _check_robot(robot)
        for name, value in (("x", x), ("y", y)):
            if isinstance(value, bool) or not isinstance(value, (int, float)) \
                    or not math.isfinite(value):
                raise RegistrationError(f"{name}: must be a finite number of metres, "
                                        f"got {value!r}")
        x, y = float(x), float(y)
        known = self._nearest(x, y)
        if known is None:
            known = _Survivor(f"{ID_PREFIX}{len(self._survivors) + 1}", x, y, found_by=robot,
                              reporter=robot, finders={robot})
            self._survivors.append(known)
            return self._answer(known, robot, zone_id, x, y, first=True)
        known.finders.add(robot)
        takeover = known.reporter is None and known.reported_by is None
        if takeover:
            known.reporter = robot
        return self._answer(known, robot, zone_id, x, y, first=False, takeover=takeover)

    def robot_lost(self, robot: str) -> tuple[str, ...]:
        """Hand back the survivors ``robot`` was to report and that are not known as reported.

        The next robot to register one of them reports it.

        Args:
            robot: The robot the fleet declared lost.

        Returns:
            The ids handed back, in id order.
        """
        handed_back = []
        for survivor in self._survivors:
            if survivor.reporter == robot and survivor.reported_by is None:
                survivor.reporter = None
                handed_back.append(survivor.survivor_id)
        return tuple(handed_back)

    def mark_reported(self, survivor_id: str) -> None:
        """Record that the base acknowledged ``survivor_id``'s report.

        Args:
            survivor_id: A registered survivor's id.

        Raises:
            KeyError: No survivor has this id.
        """
        survivor = self._by_id(survivor_id)
        if survivor.reported_by is None:
            survivor.reported_by = survivor.reporter or survivor.found_by

    def survivor_ids(self) -> tuple[str, ...]:
        """Every registered survivor's id, in registration order."""
        return tuple(s.survivor_id for s in self._survivors)

    def reporter_of(self, survivor_id: str) -> str | None:
        """The robot that reports ``survivor_id`` (None while handed back by a lost robot).

        Raises:
            KeyError: No survivor has this id.
        """
        return self._by_id(survivor_id).reporter

    def position_of(self, survivor_id: str) -> tuple[float, float]:
        """Where ``survivor_id`` was first registered.

        Raises:
            KeyError: No survivor has this id.
        """
        survivor = self._by_id(survivor_id)
        return survivor.x, survivor.y

    def __len__(self) -> int:
        return len(self._survivors)

    def _by_id(self, survivor_id: str) -> _Survivor:
        for survivor in self._survivors:
            if survivor.survivor_id == survivor_id:
                return survivor
        raise KeyError(f"no survivor {survivor_id!r} is registered")

    def _nearest(self, x: float, y: float) -> _Survivor | None:
        best: _Survivor | None = None
        best_distance = math.inf
        for survivor in self._survivors:
            distance = math.hypot(survivor.x - x, survivor.y - y)
            if distance <= self.radius_m and distance < best_distance:
                best, best_distance = survivor, distance
        return best

    @staticmethod
    def _answer(survivor: _Survivor, robot: str, zone_id: str, x: float, y: float, *,
                first: bool, takeover: bool = False) -> Registration:
        report = survivor.reporter == robot
        name = survivor.survivor_id
        if report:
            reason = ""
        elif survivor.reported_by is not None:
            reason = f"{name} was already reported by {survivor.reported_by}"
        elif survivor.reporter == survivor.found_by:
            reason = f"{name} was registered first by {survivor.found_by}, which reports it"
        else:
            reason = (f"{name} was registered first by {survivor.found_by}; "
                      f"{survivor.reporter} reports it (took it over from a lost robot)")
        return Registration(survivor_id=survivor.survivor_id, robot=robot, zone_id=zone_id,
                            x=x, y=y, report=report, found_by=survivor.found_by,
                            reason=reason, first=first, takeover=takeover)


def _check_robot(robot: object) -> None:
    if not isinstance(robot, str) or not robot:
        raise RegistrationError(f"robot: must be a non-empty name, got {robot!r}")
    if not robot.isprintable() or any(c.isspace() for c in robot):
        raise RegistrationError(f"robot: {robot!r} holds whitespace or control characters")
