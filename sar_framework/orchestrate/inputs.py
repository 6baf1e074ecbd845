"""Every input of ``sar-tree run`` checked before anything starts, all problems at once.

Checked: the files exist; ``--speed`` (the simulator's ``speed`` rule), ``--timeout`` and
``--sim-timeout``; the tree (every diagnostic) and the apps it uses
(:mod:`sar_framework.app`); the mission parameter file, the apps' default when none is named
(rcl's structure, then each key's name, type and value against the runner's table and its
apps', then each app's own checks); the survivor table; and each ``--sim-param``/
``--detect-param``/``--report-param``/``--runner-param NAME:=VALUE`` (known name,
did-you-mean, type and range, from each node's table in
:data:`NODE_PARAMETERS`; ``blocked_zones`` entries parsed, with the mission's zone names
accepted). Problems are GCC style, one a line (``file:line:col: key: problem`` where a
position is known).

No ROS is imported here: the tables live in ROS-free modules, so a bad input is reported
even where rclpy or a message package cannot be imported.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import yaml

from sar_framework.app import App, AppError, apps_for, discover_apps
from sar_framework.engine.param import Param
from sar_framework.fleet.params import COORDINATOR_PARAMETERS
from sar_framework.mission.fleet_processes import FleetMember
from sar_framework.mission.params_check import check_values, zone_positions
from sar_framework.mission.runner_params import RUNNER_PARAMETERS
from sar_framework.orchestrate.fleet_inputs import fleet_problems
from sar_framework.recording.params import RECORDER_PARAMETERS
from sar_framework.servers.params import DETECT_PARAMETERS, REPORT_PARAMETERS
from sar_framework.sim.params import SIM_PARAMETERS, SPEED, sim_default

if TYPE_CHECKING:
    from sar_framework.orchestrate.options import RunConfig

CHILDREN = ("sim", "detect", "report", "runner")
"""The children ``sar-tree run`` takes parameters for (``--sim-param`` ...)."""
NODE_PARAMETERS: dict[str, tuple[Param, ...]] = {
    "sim": SIM_PARAMETERS, "detect": DETECT_PARAMETERS, "report": REPORT_PARAMETERS,
    "runner": RUNNER_PARAMETERS, "recorder": RECORDER_PARAMETERS,
    "coordinator": COORDINATOR_PARAMETERS}
"""Each process label (:mod:`sar_framework.mission.processes`) -> its node's parameter table."""


def child_parameters(who: str) -> tuple[Param, ...]:
    """The parameters child ``who`` (``sim``, ``detect``, ``report``, ``runner``) reads."""
    return NODE_PARAMETERS[who]


def parse_entry(entry: str) -> tuple[str, Any] | None:
    """``NAME:=VALUE`` -> ``(NAME, value)`` read as YAML, as rcl reads it; None if malformed."""
    name, sep, text = entry.partition(":=")
    if not sep or not name or not all(c.isalnum() or c in "_." for c in name) \
            or name[0].isdigit() or name[0] == ".":
        return None
    try:
        value = yaml.safe_load(text)
    except yaml.YAMLError:
        value = text
    return name, text if value is None else value


@dataclass
class CheckedInputs:
    """What the checks found, for starting the mission.

    Attributes:
        spec: The tree's ``TreeSpec``.
        runner_values: The runner's parameters: the file's, then ``--runner-param``.
        zones: Mission zone id -> ``(x, y)``.
        blocked_areas: The ``blocked_zones`` fault as ``(x, y, radius)`` circles, metres.
        fleet: The fleet's robots (``--robots``/``--fleet``); empty for one robot.
        coordinator: The zone coordinator starts (a fleet whose tree bids for zones).
        apps: The apps the tree uses.
        params_file: The mission parameter file used: ``--params``, else the apps'
            default, else "" (none).
    """

    spec: Any
    runner_values: dict[str, Any]
    zones: dict[str, tuple[float, float]]
    blocked_areas: tuple[tuple[float, float, float], ...] = ()
    fleet: tuple[FleetMember, ...] = ()
    coordinator: bool = False
    apps: tuple[App, ...] = ()
    params_file: str = ""


def params_file(config: RunConfig, apps: Sequence[App]) -> str:
    """The parameter file a run uses: ``--params``, else its apps' default, else ""."""
    if config.params is not None:
        return config.params
    return next((f for f in (app.default_params_file() for app in apps) if f), "")


def _option_problems(config: RunConfig) -> list[str]:
    problems = []
    for label, path in (("tree", config.tree), ("survivor table", config.survivors)):
        if path is not None and not Path(path).is_file():
            problems.append(f"{label} not found: '{path}'")
    speed = SPEED.problem(config.speed)
    if speed is not None:
        problems.append(f"--speed {speed}")
    if not config.timeout_s > 0:
        problems.append(f"--timeout must be positive, got {config.timeout_s:g}")
    if config.sim_timeout_s is not None and not 0 < config.sim_timeout_s < math.inf:
        problems.append("--sim-timeout must be a positive number of seconds, "
                        f"got {config.sim_timeout_s:g}")
    return problems


def _entries(config: RunConfig, who: str, problems: list[str]) -> dict[str, Any]:
    values: dict[str, Any] = {}
    for entry in getattr(config, f"{who}_params"):
        parsed = parse_entry(entry)
        if parsed is None:
            problems.append(f"--{who}-param {entry!r}: expected NAME:=VALUE")
        else:
            values[parsed[0]] = parsed[1]
    return values


def _blocked_areas(values: dict[str, Any], zones: dict[str, tuple[float, float]],
                   problems: list[str], name: str = "blocked_zones"
                   ) -> tuple[tuple[float, float, float], ...]:
    """The circles of a zone-list fault (``blocked_zones``, ``phantom_obstacles``)."""
    from sar_framework.sim.faults import FaultConfigError, parse_blocked_zone
    from sar_framework.sim.world import WorldError, load_world

    entries = values.get(name)
    if not isinstance(entries, list):
        return ()
    try:
        markers = {m.name: (m.x, m.y) for m in load_world(values.get("world") or
                                                           sim_default("world")).markers}
    except WorldError:
        markers = {}
    areas = []
    for entry in entries:
        if not str(entry).strip():
            continue  # [''] means none (a ROS list cannot be empty)
        try:
            zone = parse_blocked_zone(str(entry), {**markers, **zones}, name)
        except FaultConfigError as err:
            problems.append(f"--sim-param {err}")
        else:
            areas.append((zone.x, zone.y, zone.radius))
    return tuple(areas)


def check_inputs(config: RunConfig) -> tuple[CheckedInputs | None, list[str]]:
    """Check every input of a run.

    Args:
        config: The configuration.

    Returns:
        ``(inputs, problems)``: ``inputs`` is None when a problem stops the run.
    """
    from sar_framework.engine.api import validate
    from sar_framework.mission.params_file import read_params_file
    from sar_framework.servers.survivors import SurvivorsFileError, load_survivors

    problems = _option_problems(config)
    overrides = {who: _entries(config, who, problems) for who in CHILDREN}
    for who in CHILDREN[:-1]:  # the runner's after the tree: its apps add parameters
        problems += [str(err) for err in check_values(overrides[who], child_parameters(who),
                                                      {}, f"--{who}-param")]
    spec = None
    apps: list[App] = []
    if Path(config.tree).is_file():
        result = validate(config.tree, plugin_paths=config.plugin_paths)
        problems += [str(d) for d in result.diagnostics if d.severity == "error"]
        spec = result.spec
        try:
            # A tree with errors starts nothing; its parameters are checked against every
            # installed app's, so each mistake is still reported at once.
            apps = apps_for(spec, result.registry) if spec is not None else discover_apps()
        except AppError as err:
            problems.append(f"{config.tree}: {err}")
    file = params_file(config, apps)
    table = (*RUNNER_PARAMETERS, *(p for app in apps for p in app.parameters))
    problems += [str(err) for err in check_values(overrides["runner"], table, {},
                                                  "--runner-param")]
    values: dict[str, Any] = dict(overrides["runner"])
    if file and not Path(file).is_file():
        problems.append(f"parameter file not found: '{file}'")
    elif file:
        contents = read_params_file(file)
        problems += [str(p) for p in contents.problems]
        problems += [str(p) for p in check_values(contents.values, table,
                                                  contents.locations, file)]
        values = {**contents.values, **overrides["runner"]}
        if not contents.problems:
            problems += [str(p) for app in apps if app.check is not None
                         for p in app.check(values, contents.locations, file)]
    elif apps:
        problems += [str(p) for app in apps if app.check is not None
                     for p in app.check(values, {}, "--runner-param")]
    zones = zone_positions(values)
    blocked = _blocked_areas(overrides["sim"], zones, problems)
    _blocked_areas(overrides["sim"], zones, problems, "phantom_obstacles")  # checked only
    if config.survivors is not None and Path(config.survivors).is_file():
        try:
            load_survivors(config.survivors)
        except SurvivorsFileError as err:
            problems.append(str(err))
    kinds = [node.kind for node in spec.nodes()] if spec is not None else []
    fleet, coordinator, fleet_issues = fleet_problems(config, values, overrides["sim"], kinds)
    problems += fleet_issues
    if problems or spec is None:
        return None, problems
    return CheckedInputs(spec, values, zones, blocked, fleet, coordinator, tuple(apps),
                         file), problems
