"""What a run of several robots adds to the search-and-rescue app's processes.

- The zone coordinator (``zone_coordinator``, root namespace, the mission parameter file,
  ``events_file`` in the run folder and the robots' names, whose first auction round it waits
  for) starts when the robots are named and the tree bids for zones (one of
  :data:`FLEET_LEAVES`).
- Each robot goes home to its own spawn place (its ``base_station``); without the
  coordinator robot ``i`` walks every zone from the ``i``-th (:func:`rotated`), so two robots
  never head for the same zone at once.
- ``--robots N`` spawns near the base station, off the ways from it to the zones.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from sar_plugins.sar.fleet.params import COORDINATOR_PARAMETERS

from sar_framework.app import AppProcess
from sar_framework.mission.processes import MissionSettings, ParamValue, Process, Robot

FLEET_LEAVES = frozenset({"ClaimZone", "CompleteZone", "ReleaseZone"})
"""The leaves that talk to the zone coordinator: a tree with one of them needs it."""
COORDINATOR_MODULE = "sar_plugins.sar.fleet.coordinator_node"
"""The coordinator's module (``python -m``); its console script is ``sar-zone-coordinator``."""
COORDINATOR_EVENTS_FILE = "fleet_events.jsonl"
"""The coordinator's JSON Lines events (``events_file``), in the run folder."""

COORDINATOR_KIND = AppProcess(
    "coordinator", "the fleet's zone coordinator", COORDINATOR_PARAMETERS,
    "plugins/sar/fleet/params.py", executable="sar-zone-coordinator")
"""What ``sar-tree run`` and the docs know of the coordinator."""


def uses_coordinator(settings: MissionSettings) -> bool:
    """Whether the run starts the zone coordinator: named robots, a tree that bids."""
    return settings.named_robots and not FLEET_LEAVES.isdisjoint(settings.node_kinds)


def coordinator(settings: MissionSettings) -> list[Process]:
    """The zone coordinator when the run needs it (:func:`uses_coordinator`), else none."""
    if not uses_coordinator(settings):
        return []
    parameters: dict[str, ParamValue] = {
        "use_sim_time": settings.use_sim_time,
        "events_file": str(Path(settings.run_folder) / COORDINATOR_EVENTS_FILE),
        "robots": [robot.name for robot in settings.robots]}
    files = (settings.params_file,) if settings.params_file else ()
    return [Process("coordinator", "sar-zone-coordinator", COORDINATOR_MODULE, files,
                    parameters)]


def rotated(zone_order: list[str], index: int) -> list[str]:
    """``zone_order`` started at its ``index``-th zone (wrapping): robot ``index``'s order."""
    if not zone_order:
        return []
    start = index % len(zone_order)
    return list(zone_order[start:] + zone_order[:start])


def robot_parameters(settings: MissionSettings, robot: Robot, index: int
                     ) -> dict[str, ParamValue]:
    """A named robot's home (its spawn place) and, without the coordinator, its zone order."""
    if not robot.name:
        return {}
    parameters: dict[str, ParamValue] = {"base_station.x": robot.x, "base_station.y": robot.y,
                                         "base_station.yaw": robot.yaw}
    order = settings.extra.get("runner", {}).get("zone_order")
    if order is None and settings.params_file:
        from sar_framework.mission.params_file import read_params_file

        order = read_params_file(settings.params_file).values.get("zone_order")
    if not uses_coordinator(settings) and isinstance(order, list) and order:
            parameters["zone_order"] = rotated([str(z) for z in order], index)
    return parameters


def spawn_around(values: Mapping[str, Any]) -> tuple[tuple[float, float],
                                                      list[tuple[float, float]]]:
    """The base station, and the zones whose ways from it the spawns keep clear of."""
    from sar_plugins.sar.params import zone_positions

    base = (float(values.get("base_station.x", 0.0)), float(values.get("base_station.y", 0.0)))
    return base, list(zone_positions(values).values())
