"""The simulator's run-time parameters: ``speed`` and the faults of :data:`~.params.RUNTIME_FAULTS`.

``ros2 param set /sar_sim NAME VALUE`` (or rclpy's SetParameters) reaches
:meth:`LiveParameters.on_set`: each value is checked by its table's rule (and phantom entries
are parsed) before anything changes; a bad value is refused with a reason naming the
parameter, and the simulator keeps what it had. Every other parameter is fixed.

- ``phantom_obstacles``: re-written into both costmaps at once;
- ``blocked_areas``: the walls are replaced (the planner is rebuilt);
- ``stuck_recoveries`` / ``movement_time_allowance``: the stuck controller is re-armed;
- ``speed``: handed to the physics loop.

:meth:`LiveParameters.rearm` re-applies the current values (``~/reset``).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from rcl_interfaces.msg import SetParametersResult
from rclpy.parameter import Parameter

from sar_framework.sim.costmaps import Costmaps
from sar_framework.sim.faults import (
    Circle,
    FaultConfigError,
    Faults,
    describe_circles,
    parse_circles,
)
from sar_framework.sim.navigation import Navigator
from sar_framework.sim.params import RUNTIME_NAMES, SIM_PARAMETERS, SPEED

_TABLE = {p.name: p for p in SIM_PARAMETERS}


def _plain(value: Any) -> Any:
    """A parameter value as the table's rule reads it (lists, None for unset)."""
    if isinstance(value, tuple):
        return list(value)
    if hasattr(value, "tolist"):
        return value.tolist()
    return value


class LiveParameters:
    """Checks and applies run-time changes of ``sar_sim``'s parameters.

    Args:
        faults: The faults read at start-up (the current values until changed).
        costmaps: The costmaps phantoms are written into.
        navigator: Holds the stuck controller.
        set_speed: Hands a new speed factor to the physics loop.
        log: Logs one line per change.
    """

    def __init__(self, faults: Faults, *, costmaps: Costmaps, navigator: Navigator,
                 set_speed: Callable[[float], None], log: Callable[[str], None]) -> None:
        self._costmaps = costmaps
        self._navigator = navigator
        self._set_speed = set_speed
        self._log = log
        self.phantoms: tuple[Circle, ...] = faults.phantom_obstacles
        self.stuck_recoveries = faults.stuck_recoveries
        self.movement_time_allowance = faults.movement_time_allowance

    def on_set(self, params: list[Parameter]) -> SetParametersResult:
        """The ``add_on_set_parameters_callback`` callback: all values are checked first."""
        changes: dict[str, Any] = {}
        for param in params:
            name = param.name
            if name == "use_sim_time":
                continue
            if name in _TABLE and name not in RUNTIME_NAMES:
                return SetParametersResult(
                    successful=False, reason=f"{name} cannot change at run time "
                    f"(run-time parameters: {', '.join(sorted(RUNTIME_NAMES))})")
            if name not in _TABLE:
                continue
            value = None if param.type_ == Parameter.Type.NOT_SET else _plain(param.value)
            problem = None if value is None else _TABLE[name].problem(value)
            if problem is not None:
                return SetParametersResult(successful=False, reason=f"{name}: {problem}")
            if name in ("phantom_obstacles", "blocked_areas"):
                try:
                    value = parse_circles(value or (), {}, name)
                except FaultConfigError as exc:
                    return SetParametersResult(successful=False, reason=str(exc))
            elif value is None:
                return SetParametersResult(successful=False, reason=f"{name}: must be set")
            changes[name] = value
        self._apply(changes)
        return SetParametersResult(successful=True)

    def _apply(self, changes: dict[str, Any]) -> None:
        if SPEED.name in changes:
            speed = float(changes[SPEED.name])
            self._set_speed(speed)
            self._log(f"Speed set to {speed:g}x real time.")
        if "phantom_obstacles" in changes:
            self.phantoms = changes["phantom_obstacles"]
            self._costmaps.write(self.phantoms)
            self._log("phantom_obstacles written into both costmaps: "
                      f"{describe_circles(self.phantoms) or 'none'}")
        if "blocked_areas" in changes:
            self._costmaps.set_walls(changes["blocked_areas"])
            self._log("blocked_areas (walls) now: "
                      f"{describe_circles(changes['blocked_areas']) or 'none'}")
        if {"stuck_recoveries", "movement_time_allowance"} & changes.keys():
            self.stuck_recoveries = int(changes.get("stuck_recoveries", self.stuck_recoveries))
            self.movement_time_allowance = float(
                changes.get("movement_time_allowance", self.movement_time_allowance))
            self._navigator.set_stuck(self.stuck_recoveries, self.movement_time_allowance)
            self._log(f"Controller stuck for {self.stuck_recoveries} recoveries (fails after "
                      f"{self.movement_time_allowance:g} s without progress).")

    def rearm(self) -> None:
        """Write the current phantoms into both costmaps and re-arm the stuck controller."""
        self._costmaps.write(self.phantoms)
        self._navigator.set_stuck(self.stuck_recoveries, self.movement_time_allowance)
