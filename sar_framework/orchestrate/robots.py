"""The robots of a ``sar-tree run``, checked before anything starts (no ROS).

One unnamed robot by default (:data:`~sar_framework.mission.processes.ONE_ROBOT`);
``--robots N`` names N (1 to :data:`~sar_framework.sim.spawn_poses.MAX_ROBOTS`, spawn places
found in the simulator's map around where the tree's apps say,
:attr:`~sar_framework.app.App.spawn_around`), ``--fleet FILE`` names those of a fleet file
(every problem as ``file:line:col: problem``, spawns closer than two footprints), never
both; and what named robots cannot do yet (``--record``, ``--watch``: one robot's topics;
``--keep-alive``).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from sar_framework.mission.processes import ONE_ROBOT, Robot
from sar_framework.sim.params import sim_default

if TYPE_CHECKING:
    from sar_framework.app import App
    from sar_framework.orchestrate.options import RunConfig

FLEET_FILE = "fleet.yaml"
"""The fleet file ``--robots N`` writes, in the run folder."""


def _robot_radius(sim_values: dict[str, Any]) -> float:
    radius = sim_values.get("robot_radius")
    if isinstance(radius, (int, float)) and not isinstance(radius, bool) and radius > 0:
        return float(radius)
    return float(sim_default("robot_radius"))


def spawn_around(values: dict[str, Any], apps: Sequence[App]
                 ) -> tuple[tuple[float, float], list[tuple[float, float]]]:
    """Where named robots spawn: the first app's say, else around ``initial_pose``."""
    for app in apps:
        if app.spawn_around is not None:
            return app.spawn_around(values)
    return (float(values.get("initial_pose.x", 0.0)),
            float(values.get("initial_pose.y", 0.0))), []


def _generated(count: int, values: dict[str, Any], sim_values: dict[str, Any],
               apps: Sequence[App], problems: list[str]) -> tuple[Robot, ...]:
    from sar_framework.sim.occupancy import MapError, load_map
    from sar_framework.sim.spawn_poses import MAX_ROBOTS, SpawnError, spawn_poses

    if not 1 <= count <= MAX_ROBOTS:
        problems.append(f"--robots must be between 1 and {MAX_ROBOTS}, got {count}")
        return ()
    centre, places = spawn_around(values, apps)
    map_yaml = sim_values.get("map_yaml") or sim_default("map_yaml")
    try:
        poses = spawn_poses(count, centre, load_map(map_yaml), _robot_radius(sim_values),
                            destinations=places)
    except (MapError, SpawnError) as err:
        problems.append(f"--robots {count}: {err}")
        return ()
    return tuple(Robot(f"robot{i}", p.x, p.y, p.yaw) for i, p in enumerate(poses, 1))


def read_robots(fleet_file: str | Path) -> tuple[Robot, ...]:
    """The robots of a fleet file, in file order.

    Raises:
        FleetFileError: Every problem of the file, each as ``file:line:col: problem``.
    """
    from sar_framework.sim.fleet_file import load_fleet

    return tuple(Robot(r.name, r.spawn.x, r.spawn.y, r.spawn.yaw) for r in load_fleet(fleet_file))


def _from_file(path: str, sim_values: dict[str, Any],
               problems: list[str]) -> tuple[Robot, ...]:
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
    return () if crowded else read_robots(path)


def robot_problems(config: RunConfig, values: dict[str, Any], sim_values: dict[str, Any],
                   apps: Sequence[App]) -> tuple[tuple[Robot, ...], list[str]]:
    """Check the robots of a run.

    Args:
        config: The configuration (``robots``, ``fleet``).
        values: The runner's parameters (where the apps spawn robots).
        sim_values: The ``--sim-param`` values (``map_yaml``, ``robot_radius``).
        apps: The tree's apps.

    Returns:
        ``(robots, problems)``: :data:`ONE_ROBOT` unless the run names its robots.
    """
    problems: list[str] = []
    if not config.names_robots:
        return ONE_ROBOT, problems
    if config.robots is not None and config.fleet is not None:
        problems.append("--robots and --fleet: give one of them (--fleet names its robots)")
        return (), problems
    for given, what in ((config.record, "--record"), (config.watch, "--watch")):
        if given:
            problems.append(f"{what} follows one robot's topics: not with a fleet yet "
                            "(sar-tree watch --namespace robot1 watches one robot)")
    if config.keep_alive:
        problems.append("--keep-alive: not with a fleet yet (the fleet's verdict waits for "
                        "every runner to end)")
    robots = (_generated(config.robots, values, sim_values, apps, problems)
              if config.robots is not None else _from_file(str(config.fleet), sim_values,
                                                            problems))
    return robots, problems


def fleet_file(config: RunConfig, report_dir: Path) -> Path:
    """The fleet file the simulator reads: ``--fleet``'s, or the one ``--robots`` writes."""
    return Path(config.fleet).resolve() if config.fleet else report_dir / FLEET_FILE


def write_fleet_file(config: RunConfig, report_dir: Path, robots: Sequence[Robot]) -> Path:
    """Write ``--robots``' fleet file into the report folder (``--fleet``'s is used as is)."""
    from sar_framework.sim.spawn_poses import fleet_text
    from sar_framework.sim.world import Pose2D

    path = fleet_file(config, report_dir)
    if not config.fleet:
        path.write_text(fleet_text([Pose2D(r.x, r.y, r.yaw) for r in robots]),
                        encoding="utf-8")
    return path
