"""The fleet options of ``sar-tree run`` checked before anything starts (no ROS).

``--robots N`` (1 to :data:`~sar_framework.sim.spawn_poses.MAX_ROBOTS`, spawn places found
in the simulator's map near the mission's base station) or ``--fleet FILE`` (every problem
of the file as ``file:line:col: problem``, spawns closer than two footprints), never both;
and what a fleet cannot do yet (``--record``, ``--watch``: one robot's topics;
``--keep-alive``). Whether the
zone coordinator starts is decided here too: when the tree uses a leaf that bids for zones
(:data:`~sar_framework.mission.fleet_processes.FLEET_LEAVES`), and then it must be installed.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path
from typing import TYPE_CHECKING, Any

from sar_plugins.sar.params import zone_positions

from sar_framework.mission.fleet_processes import (
    COORDINATOR_MODULE,
    FLEET_LEAVES,
    FleetMember,
    tree_uses_coordinator,
)
from sar_framework.sim.params import sim_default

if TYPE_CHECKING:
    from sar_framework.orchestrate.options import RunConfig


def coordinator_installed() -> bool:
    """Whether the zone coordinator's module can be imported."""
    try:
        return importlib.util.find_spec(COORDINATOR_MODULE) is not None
    except ImportError:  # its package is missing
        return False


def _robot_radius(sim_values: dict[str, Any]) -> float:
    from sar_framework.sim.world import WorldError, load_world

    radius = sim_values.get("robot_radius")
    if isinstance(radius, (int, float)) and not isinstance(radius, bool) and radius > 0:
        return float(radius)
    try:
        return load_world(sim_values.get("world") or sim_default("world")).robot.footprint_radius
    except WorldError:
        return 0.22


def _generated(count: int, mission: dict[str, Any], sim_values: dict[str, Any],
               problems: list[str]) -> tuple[FleetMember, ...]:
    from sar_framework.sim.occupancy import MapError, load_map
    from sar_framework.sim.spawn_poses import MAX_ROBOTS, SpawnError, spawn_poses

    if not 1 <= count <= MAX_ROBOTS:
        problems.append(f"--robots must be between 1 and {MAX_ROBOTS}, got {count}")
        return ()
    base = (float(mission.get("base_station.x", 0.0)), float(mission.get("base_station.y", 0.0)))
    map_yaml = sim_values.get("map_yaml") or sim_default("map_yaml")
    try:
        poses = spawn_poses(count, base, load_map(map_yaml), _robot_radius(sim_values),
                            zones=list(zone_positions(mission).values()))
    except (MapError, SpawnError) as err:
        problems.append(f"--robots {count}: {err}")
        return ()
    return tuple(FleetMember(f"robot{i}", p.x, p.y, p.yaw) for i, p in enumerate(poses, 1))


def read_members(fleet_file: str | Path) -> tuple[FleetMember, ...]:
    """The robots of a fleet file, in file order.

    Raises:
        FleetFileError: Every problem of the file, each as ``file:line:col: problem``.
    """
    from sar_framework.sim.fleet_file import load_fleet

    return tuple(FleetMember(r.name, r.spawn.x, r.spawn.y, r.spawn.yaw)
                 for r in load_fleet(fleet_file))


def _from_file(path: str, sim_values: dict[str, Any],
               problems: list[str]) -> tuple[FleetMember, ...]:
    from sar_framework.sim.fleet_file import FleetFileError, crowded_spawns, load_fleet

    if not Path(path).is_file():
        problems.append(f"fleet file not found: '{path}'")
        return ()
    try:
        robots = load_fleet(path)
    except FleetFileError as err:
        problems += str(err).splitlines()
        return ()
    crowded = crowded_spawns(robots, 2.0 * _robot_radius(sim_values))
    problems += crowded
    return () if crowded else tuple(FleetMember(r.name, r.spawn.x, r.spawn.y, r.spawn.yaw)
                                    for r in robots)


def fleet_problems(config: RunConfig, mission: dict[str, Any], sim_values: dict[str, Any],
                   node_kinds: list[str]) -> tuple[tuple[FleetMember, ...], bool, list[str]]:
    """Check the fleet options of a run.

    Args:
        config: The configuration (``robots``, ``fleet``).
        mission: The runner's parameters (``base_station.*``).
        sim_values: The ``--sim-param`` values (``map_yaml``, ``world``, ``robot_radius``).
        node_kinds: The tree's node kinds (empty when the tree did not load).

    Returns:
        ``(robots, coordinator, problems)``: the fleet (empty for one robot), whether the
        zone coordinator starts, and every problem found.
    """
    problems: list[str] = []
    uses = tree_uses_coordinator(node_kinds)
    if not config.is_fleet:
        return (), False, problems
    if config.robots is not None and config.fleet is not None:
        problems.append("--robots and --fleet: give one of them (--fleet names its robots)")
        return (), uses, problems
    for given, what in ((config.record, "--record"), (config.watch, "--watch")):
        if given:
            problems.append(f"{what} follows one robot's topics: not with a fleet yet "
                            "(sar-tree watch --namespace robot1 watches one robot)")
    if config.keep_alive:
        problems.append("--keep-alive: not with a fleet yet (the fleet's verdict waits for "
                        "every runner to end)")
    if uses and not coordinator_installed():
        leaves = ", ".join(sorted(FLEET_LEAVES.intersection(node_kinds)))
        problems.append(f"{config.tree}: the tree bids for zones ({leaves}) but the zone "
                        f"coordinator ({COORDINATOR_MODULE}) is not installed")
    robots = (_generated(config.robots, mission, sim_values, problems)
              if config.robots is not None else _from_file(str(config.fleet), sim_values,
                                                            problems))
    return robots, uses, problems
