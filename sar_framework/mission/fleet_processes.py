"""A fleet's processes: one simulator, the base and the coordinator, a runner per robot.

The fleet twin of :func:`~sar_framework.mission.processes.mission_processes`, built from
the same :class:`~sar_framework.mission.processes.MissionSettings` and the same process
builders, so ``sar-tree run --robots N``/``--fleet FILE`` and ``fleet.launch.py`` start
the same thing (no ROS imported here). In start order:

- the simulator (``sar-sim``) with ``fleet_file``: one process serves every robot, each
  under ``/<name>`` (docs/how-to/fleet.md); its trace, one per robot, goes to ``RUN/<name>/``;
- the base's report server, in the root namespace: one base serves the fleet;
- the zone coordinator (``sar_plugins.sar.fleet.coordinator_node``, node ``zone_coordinator``,
  root namespace) with the mission parameter file and ``events_file`` in the run folder,
  when the tree bids for its zones (:func:`tree_uses_coordinator`);
- per robot, in ``/<name>``: a detect server and a runner, whose ``initial_pose`` and
  ``base_station`` are the robot's spawn pose from the fleet file (each robot goes home to
  its own place near the base, not all to one point), and whose status and events go to
  ``RUN/<name>/``; without the coordinator robot ``i`` walks the zones from the ``i``-th.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, replace
from pathlib import Path

from sar_framework.mission.processes import (
    MissionSettings,
    ParamValue,
    Process,
    ProcessSource,
    app_processes,
    runner,
    simulator,
    with_extra,
)

FLEET_LEAVES = frozenset({"ClaimZone", "CompleteZone", "ReleaseZone"})
"""The leaves that talk to the zone coordinator: a tree with one of them needs it."""
COORDINATOR_MODULE = "sar_plugins.sar.fleet.coordinator_node"
"""The coordinator's module (``python -m``); its console script is ``sar-zone-coordinator``."""
COORDINATOR_EVENTS_FILE = "fleet_events.jsonl"
"""The coordinator's JSON Lines events (``events_file``), in the run folder."""
FLEET_FILE = "fleet.yaml"
"""The fleet file ``--robots N`` writes, in the run folder."""


@dataclass(frozen=True)
class FleetMember:
    """One robot of the fleet as its processes need it.

    Attributes:
        name: Its namespace (``robot1``).
        x: Spawn x, metres (map frame).
        y: Spawn y, metres.
        yaw: Spawn heading, radians.
    """

    name: str
    x: float
    y: float
    yaw: float = 0.0


def tree_uses_coordinator(kinds: Iterable[str]) -> bool:
    """Whether a tree with these node kinds bids for zones (:data:`FLEET_LEAVES`)."""
    return not FLEET_LEAVES.isdisjoint(kinds)


@dataclass(frozen=True)
class FleetSettings:
    """What a fleet mission starts, beyond one robot's :class:`MissionSettings`.

    Attributes:
        mission: The mission's settings (tree, parameter file, speed, servers...); its
            ``trace_file`` is the run folder's ``trace.jsonl`` (each robot's goes to
            ``RUN/<name>/``) and its ``status_file``/``recorder`` are not used.
        fleet_file: The fleet file the simulator reads.
        robots: The robots of that file.
        run_dir: The run folder (``RUN/<name>/`` holds a robot's status and events).
        coordinator: Start the zone coordinator.
        zone_order: The mission's ``zone_order``: without the coordinator each robot walks
            every zone, robot ``i`` starting at zone ``i`` (:func:`rotated`), so two robots
            never head for the same zone at once; empty: the parameter file's order for all.
        apps: The tree's apps: their processes start once, or once per robot in its
            namespace (an :class:`~sar_framework.app.AppProcess` with ``per_robot``).
    """

    mission: MissionSettings
    fleet_file: str
    robots: tuple[FleetMember, ...]
    run_dir: str
    coordinator: bool = False
    zone_order: tuple[str, ...] = ()
    apps: tuple[ProcessSource, ...] = ()

    def robot_dir(self, name: str) -> Path:
        """``RUN/<name>``: a robot's status, events, trace and report."""
        return Path(self.run_dir) / name

    @property
    def coordinator_events(self) -> Path:
        """The coordinator's ``events_file``."""
        return Path(self.run_dir) / COORDINATOR_EVENTS_FILE


def coordinator(settings: FleetSettings) -> Process | None:
    """The zone coordinator, in the root namespace, with the mission parameter file."""
    if not settings.coordinator:
        return None
    m = settings.mission
    parameters: dict[str, ParamValue] = {
        "use_sim_time": m.use_sim_time, "events_file": str(settings.coordinator_events)}
    return Process("coordinator", "sar-zone-coordinator", COORDINATOR_MODULE,
                   (m.params_file,), parameters)


def rotated(zone_order: tuple[str, ...], index: int) -> list[str]:
    """``zone_order`` started at its ``index``-th zone (wrapping): robot ``index``'s order."""
    if not zone_order:
        return []
    start = index % len(zone_order)
    return list(zone_order[start:] + zone_order[:start])


def _per_robot(settings: FleetSettings) -> set[str]:
    """The labels of the apps' processes each robot starts its own of."""
    return {kind.label for app in settings.apps for kind in app.process_kinds if kind.per_robot}


def robot_processes(settings: FleetSettings, robot: FleetMember, index: int = 0
                    ) -> list[Process]:
    """One robot's own app processes and runner, in ``/<name>`` (``index``: its place)."""
    m = settings.mission
    folder = settings.robot_dir(robot.name)
    own = replace(m, status_file=str(folder / "status.json"))
    processes = [replace(p, namespace=robot.name)
                 for p in app_processes(own, settings.apps) if p.label in _per_robot(settings)]
    tree_runner = runner(own)
    assert tree_runner is not None
    pose: dict[str, ParamValue] = {}
    for prefix in ("initial_pose", "base_station"):
        pose.update({f"{prefix}.x": robot.x, f"{prefix}.y": robot.y,
                     f"{prefix}.yaw": robot.yaw})
    if settings.zone_order and not settings.coordinator:
        pose["zone_order"] = rotated(settings.zone_order, index)
    processes.append(replace(tree_runner, namespace=robot.name,
                             parameters={**tree_runner.parameters, **pose}))
    return processes


def fleet_processes(settings: FleetSettings) -> list[Process]:
    """The fleet's processes in start order (the runners last), each with its parameters.

    Args:
        settings: What the fleet starts.

    Returns:
        One description per process; ``mission.extra`` is applied last, by label (every
        robot's runner takes ``extra["runner"]``).
    """
    m = settings.mission
    processes: list[Process] = []
    sim = simulator(m)
    if sim is not None:
        processes.append(replace(sim, parameters={**sim.parameters,
                                                  "fleet_file": settings.fleet_file}))
    processes += [p for p in app_processes(m, settings.apps)
                  if p.label not in _per_robot(settings)]
    shared = coordinator(settings)
    if shared is not None:
        processes.append(shared)
    servers = [p for i, robot in enumerate(settings.robots)
               for p in robot_processes(settings, robot, i)]
    processes += [p for p in servers if p.label != "runner"]
    processes += [p for p in servers if p.label == "runner"]
    return [with_extra(p, m) for p in processes]
