"""Fault injection: rejected, aborted and late goals, blocked areas of the map.

``sar-tree faults`` lists every fault ``sar-tree run`` can inject
(:mod:`sar_framework.orchestrate.faults`, from the parameter tables).

Plain Python (no ROS). The simulator node reads these settings from its parameters:

- ``reject_goals``: every ``navigate_to_pose`` goal is rejected.
- ``abort_goal_numbers``: the N-th accepted goals (1-based) abort ``abort_delay_s``
  simulated seconds after they start, as a failing controller would.
- ``accept_delay_wall_s``: the server answers a goal request only after this many *wall*
  seconds (client time-outs are wall-clock bounds, so the delay is too).
- ``blocked_areas``: circles added to the map as obstacles before planning. Each entry is
  ``"x:y:radius"`` (``,`` or spaces also separate). The simulator knows no names; a caller
  that knows named places passes them to :func:`parse_circle` (``sar-tree run`` accepts the
  names its app gives, ``"name"`` or ``"name:0.8"``, and turns them into ``x:y:radius``).
- ``phantom_obstacles``: circles, same syntax, written into both costmaps (never into the
  map); costmap clearing removes them (:mod:`.costmaps`). Settable at run time.
- ``stuck_recoveries`` / ``movement_time_allowance``: the controller makes no progress and
  fails after the allowance until that many recovery motions have completed
  (:mod:`.navigation`). Settable at run time.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field

import numpy as np

from sar_framework.sim.occupancy import OCCUPIED, OccupancyGrid
from sar_framework.sim.params import DEFAULT_NAMED_RADIUS

__all__ = ["DEFAULT_NAMED_RADIUS", "Circle", "FaultConfigError", "Faults", "describe_circles",
           "make_faults", "parse_circle", "parse_circles", "with_circles"]

_SEPARATORS = re.compile(r"[:,\s]+")


class FaultConfigError(ValueError):
    """A fault-injection setting is malformed; the message names the setting."""


@dataclass(frozen=True)
class Circle:
    """A circular area the planner must treat as an obstacle.

    Attributes:
        x: Centre x, metres (map frame).
        y: Centre y, metres (map frame).
        radius: Metres.
        label: The text it was parsed from, for log messages.
    """

    x: float
    y: float
    radius: float
    label: str = ""


def _number(text: str, entry: str, setting: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise FaultConfigError(
            f"{setting}: {entry!r}: {text!r} is not a number (expected 'x:y:radius' "
            "or 'name[:radius]')"
        ) from None
    if not math.isfinite(value):
        raise FaultConfigError(f"{setting}: {entry!r}: {text!r} is not finite")
    return value


def parse_circle(entry: str, places: Mapping[str, tuple[float, float]],
                 setting: str = "blocked_areas") -> Circle:
    """Parse one ``blocked_areas`` (or ``phantom_obstacles``) entry.

    Args:
        entry: ``"x:y:radius"``, or ``"name"`` / ``"name:radius"`` of one of ``places``.
        places: Named places the caller knows and their ``(x, y)`` centres ({}: none).
        setting: The parameter it comes from (named in errors).

    Returns:
        The circle.

    Raises:
        FaultConfigError: Unknown name, wrong number of fields, or a bad number.
    """
    parts = [p for p in _SEPARATORS.split(entry.strip()) if p]
    if not parts:
        raise FaultConfigError(f"{setting}: empty entry")
    if parts[0] in places:
        if len(parts) > 2:
            raise FaultConfigError(f"{setting}: {entry!r}: expected 'name[:radius]'")
        x, y = places[parts[0]]
        radius = _number(parts[1], entry, setting) if len(parts) == 2 else DEFAULT_NAMED_RADIUS
    elif len(parts) == 3:
        x, y, radius = (_number(p, entry, setting) for p in parts)
    elif places:
        raise FaultConfigError(
            f"{setting}: {entry!r}: expected 'x:y:radius' or a place's name "
            f"(known: {', '.join(sorted(places))})"
        )
    else:
        raise FaultConfigError(f"{setting}: {entry!r}: expected 'x:y:radius'")
    if radius <= 0.0:
        raise FaultConfigError(f"{setting}: {entry!r}: radius must be positive")
    return Circle(x=x, y=y, radius=radius, label=entry)


def parse_circles(entries: Iterable[str], places: Mapping[str, tuple[float, float]],
                  setting: str) -> tuple[Circle, ...]:
    """Parse a list of circle entries; empty strings are ignored (``['']`` means none).

    Raises:
        FaultConfigError: An entry is malformed (the message names ``setting``).
    """
    return tuple(parse_circle(entry, places, setting)
                 for entry in entries if entry.strip())


@dataclass(frozen=True)
class Faults:
    """The fault-injection settings of one simulator run.

    Attributes:
        reject_goals: Reject every goal.
        abort_goal_numbers: 1-based numbers of the accepted goals that abort.
        abort_delay_s: Simulated seconds an injected abort waits after the goal starts.
        accept_delay_wall_s: Wall seconds before a goal request is answered.
        blocked_areas: Extra circular obstacles.
        phantom_obstacles: Circles in both costmaps (clearing removes them) at start-up.
        stuck_recoveries: Recovery motions a stuck controller needs at start-up.
        movement_time_allowance: Simulated seconds before a stuck controller fails.
    """

    reject_goals: bool = False
    abort_goal_numbers: frozenset[int] = field(default_factory=frozenset)
    abort_delay_s: float = 1.0
    accept_delay_wall_s: float = 0.0
    blocked_areas: tuple[Circle, ...] = ()
    phantom_obstacles: tuple[Circle, ...] = ()
    stuck_recoveries: int = 0
    movement_time_allowance: float = 10.0

    def aborts(self, goal_number: int) -> bool:
        """Return True if the ``goal_number``-th accepted goal (1-based) must abort."""
        return goal_number in self.abort_goal_numbers

    @property
    def any(self) -> bool:
        """Whether any fault is configured (for a start-up log line)."""
        return bool(
            self.reject_goals
            or self.abort_goal_numbers
            or self.accept_delay_wall_s > 0.0
            or self.blocked_areas
            or self.phantom_obstacles
            or self.stuck_recoveries
        )

    def describe(self) -> str:
        """Return the configured faults in one line, e.g. for the start-up log."""
        parts = []
        if self.reject_goals:
            parts.append("reject_goals")
        if self.abort_goal_numbers:
            numbers = ", ".join(str(n) for n in sorted(self.abort_goal_numbers))
            parts.append(f"abort goals [{numbers}] after {self.abort_delay_s:g} s")
        if self.accept_delay_wall_s > 0.0:
            parts.append(f"accept after {self.accept_delay_wall_s:g} s wall")
        if self.blocked_areas:
            parts.append(f"blocked areas {describe_circles(self.blocked_areas)}")
        if self.phantom_obstacles:
            parts.append(f"phantom obstacles {describe_circles(self.phantom_obstacles)}")
        if self.stuck_recoveries:
            parts.append(f"stuck for {self.stuck_recoveries} recoveries "
                         f"(fails after {self.movement_time_allowance:g} s)")
        return "; ".join(parts) or "none"


def make_faults(
    *,
    reject_goals: bool = False,
    abort_goal_numbers: Iterable[int] = (),
    abort_delay_s: float = 1.0,
    accept_delay_wall_s: float = 0.0,
    blocked_areas: Iterable[str] = (),
    phantom_obstacles: Iterable[str] = (),
    stuck_recoveries: int = 0,
    movement_time_allowance: float = 10.0,
) -> Faults:
    """Validate raw settings (as read from ROS parameters) into :class:`Faults`.

    Empty strings in ``blocked_areas`` and zeros in ``abort_goal_numbers`` are ignored:
    ROS parameters cannot hold an empty typed list, so ``['']`` and ``[0]`` mean "none".

    Args:
        reject_goals: Reject every goal.
        abort_goal_numbers: 1-based accepted-goal numbers to abort.
        abort_delay_s: Simulated seconds before an injected abort.
        accept_delay_wall_s: Wall seconds before a goal request is answered.
        blocked_areas: Entries for :func:`parse_circle` (``x:y:radius``).
        phantom_obstacles: Entries for :func:`parse_circle`, as ``blocked_areas``.
        stuck_recoveries: Recovery motions a stuck controller needs (>= 0).
        movement_time_allowance: Seconds a stuck controller runs before it fails (> 0).

    Returns:
        The settings.

    Raises:
        FaultConfigError: A setting is out of range or malformed.
    """
    numbers = frozenset(int(n) for n in abort_goal_numbers if int(n) != 0)
    if any(n < 0 for n in numbers):
        raise FaultConfigError(
            f"abort_goal_numbers: goal numbers are 1-based, got {sorted(numbers)}"
        )
    for name, value in (("abort_delay_s", abort_delay_s),
                        ("accept_delay_wall_s", accept_delay_wall_s)):
        if not (math.isfinite(value) and value >= 0.0):
            raise FaultConfigError(f"{name}: expected a number >= 0, got {value!r}")
    if int(stuck_recoveries) < 0:
        raise FaultConfigError(f"stuck_recoveries: expected an integer >= 0, "
                               f"got {stuck_recoveries!r}")
    if not (math.isfinite(movement_time_allowance) and movement_time_allowance > 0.0):
        raise FaultConfigError(f"movement_time_allowance: expected a number > 0, "
                               f"got {movement_time_allowance!r}")
    areas = parse_circles(blocked_areas, {}, "blocked_areas")
    return Faults(
        reject_goals=bool(reject_goals),
        abort_goal_numbers=numbers,
        abort_delay_s=float(abort_delay_s),
        accept_delay_wall_s=float(accept_delay_wall_s),
        blocked_areas=areas,
        phantom_obstacles=parse_circles(phantom_obstacles, {}, "phantom_obstacles"),
        stuck_recoveries=int(stuck_recoveries),
        movement_time_allowance=float(movement_time_allowance),
    )


def describe_circles(circles: Iterable[Circle]) -> str:
    """Circles in one line for a log: ``(1, -0.5, r 0.3), ...`` ("" for none)."""
    return ", ".join(f"({c.x:g}, {c.y:g}, r {c.radius:g})" for c in circles)


def with_circles(grid: OccupancyGrid, circles: Iterable[Circle]) -> OccupancyGrid:
    """Return a copy of ``grid`` with every cell whose centre lies in a circle made occupied.

    Args:
        grid: The map.
        circles: Circles to add.

    Returns:
        A new grid (``grid`` is left unchanged).
    """
    data = grid.data.copy()
    xs, ys = grid.cell_centres()
    for circle in circles:
        inside = (xs[np.newaxis, :] - circle.x) ** 2 + (ys[:, np.newaxis] - circle.y) ** 2
        data[inside <= circle.radius**2] = OCCUPIED
    return OccupancyGrid(
        data=data, resolution=grid.resolution, origin_x=grid.origin_x, origin_y=grid.origin_y
    )
