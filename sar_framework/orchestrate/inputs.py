"""Every input of ``sar-tree run`` checked before anything starts, all problems at once.

Checked: the files exist; ``--speed`` (the simulator's ``speed`` rule), ``--timeout`` and
``--sim-timeout``; the tree (every diagnostic) and the apps it uses
(:mod:`sar_framework.app`); the mission parameter file, the apps' default when none is named
(rcl's structure, then each key's name, type and value against the runner's table and its
apps', then each app's own checks); the apps' file options (a file option: the file
exists, the app's check of it); and each ``--sim-param``/``--runner-param`` and app
process's ``--LABEL-param NAME:=VALUE`` (known name, did-you-mean, type and range, from each
node's table, :func:`node_parameters`; ``blocked_areas`` entries parsed, with the apps' place
names accepted). Problems are GCC style, one a line (``file:line:col: key: problem`` where a
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

from sar_framework.app import App, AppError, AppOption, apps_for, discover_apps, installed_apps
from sar_framework.engine.param import Param
from sar_framework.mission.params_check import check_values
from sar_framework.mission.processes import ONE_ROBOT, Robot
from sar_framework.mission.runner_params import RUNNER_PARAMETERS
from sar_framework.orchestrate.robots import robot_problems
from sar_framework.recording.params import RECORDER_PARAMETERS
from sar_framework.sim.params import SIM_PARAMETERS, SPEED

if TYPE_CHECKING:
    from sar_framework.orchestrate.options import RunConfig

NODE_PARAMETERS: dict[str, tuple[Param, ...]] = {
    "sim": SIM_PARAMETERS, "runner": RUNNER_PARAMETERS, "recorder": RECORDER_PARAMETERS}
"""The core's process labels (:mod:`sar_framework.mission.processes`) -> each node's
parameter table; the apps' processes declare their own (:func:`node_parameters`)."""


def node_parameters(apps: Sequence[App] | None = None) -> dict[str, tuple[Param, ...]]:
    """Each process label -> its node's parameter table: the core's, then the apps'.

    Args:
        apps: The apps whose processes count (default: the installed ones).
    """
    if apps is None:
        apps = installed_apps()
    tables = dict(NODE_PARAMETERS)
    tables.update({kind.label: kind.parameters for app in apps for kind in app.process_kinds})
    return tables


def child_parameters(who: str) -> tuple[Param, ...]:
    """The parameters child ``who`` (``sim``, ``runner``, an installed app's ``detect``) reads."""
    return node_parameters()[who]


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
        places: The apps' place name -> ``(x, y)``.
        blocked_areas: The ``blocked_areas`` fault as ``(x, y, radius)`` circles, metres.
        robots: The robots (``--robots``/``--fleet`` name them; one unnamed by default).
        apps: The apps the tree uses.
        params_file: The mission parameter file used: ``--params``, else the apps'
            default, else "" (none).
        node_kinds: The tree's node kinds.
    """

    spec: Any
    runner_values: dict[str, Any]
    places: dict[str, tuple[float, float]]
    blocked_areas: tuple[tuple[float, float, float], ...] = ()
    robots: tuple[Robot, ...] = ONE_ROBOT
    apps: tuple[App, ...] = ()
    params_file: str = ""
    node_kinds: frozenset[str] = frozenset()


def params_file(config: RunConfig, apps: Sequence[App]) -> str:
    """The parameter file a run uses: ``--params``, else its apps' default, else ""."""
    if config.params is not None:
        return config.params
    return next((f for f in (app.default_params_file() for app in apps) if f), "")


def app_options(config: RunConfig, apps: Sequence[App]) -> list[tuple[AppOption, str]]:
    """The apps' file options given (``--table FILE``), each with its file.

    The installed apps' options count beside ``apps``: an option of an app the tree does
    not use is still checked.
    """
    known = {option.flag: option for app in (*apps, *installed_apps())
             for option in app.options}
    return [(known[flag], path) for flag, path in config.app_options.items() if flag in known]


def _option_problems(config: RunConfig) -> list[str]:
    problems = []
    for label, path in (("tree", config.tree),
                        *((option.what, path) for option, path in app_options(config, ()))):
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
    given = (config.app_params.get(who, []) if who not in ("sim", "runner")
             else config.sim_entries if who == "sim" else config.runner_params)
    for entry in given:
        parsed = parse_entry(entry)
        if parsed is None:
            problems.append(f"--{who}-param {entry!r}: expected NAME:=VALUE")
        else:
            values[parsed[0]] = parsed[1]
    return values


def _blocked_areas(values: dict[str, Any], places: dict[str, tuple[float, float]],
                   problems: list[str], name: str = "blocked_areas"
                   ) -> tuple[tuple[float, float, float], ...]:
    """The circles of an area-list fault (``blocked_areas``, ``phantom_obstacles``)."""
    entries = values.get(name)
    if not isinstance(entries, list):
        return ()
    from sar_framework.sim.faults import FaultConfigError, parse_circle  # numpy: only if used

    areas = []
    for entry in entries:
        if not str(entry).strip():
            continue  # [''] means none (a ROS list cannot be empty)
        try:
            area = parse_circle(str(entry), places, name)
        except FaultConfigError as err:
            problems.append(f"--sim-param {err}")
        else:
            areas.append((area.x, area.y, area.radius))
    return tuple(areas)


def _map_problems(config: RunConfig, values: dict[str, Any]) -> list[str]:
    """The simulator's map (``--map``) read as map_server reads it, the spawn pose free on it."""
    if not config.sim or not {"map_yaml", "spawn_x", "spawn_y"} & values.keys():
        return []
    from sar_framework.sim.occupancy import MapError, load_map, spawn_problem
    from sar_framework.sim.params import sim_default

    flag = "--map" if config.map else "--sim-param map_yaml"
    map_yaml = str(values.get("map_yaml") or sim_default("map_yaml"))
    try:
        grid = load_map(map_yaml)
    except MapError as err:
        return [f"{flag}: {err}"]
    x, y = (values.get(name, sim_default(name)) for name in ("spawn_x", "spawn_y"))
    if config.names_robots or not all(isinstance(v, (int, float)) for v in (x, y)):
        return []  # a fleet's spawn poses are checked with the fleet; a bad type already was
    problem = spawn_problem(grid, float(x), float(y))
    where = "--spawn" if config.spawn is not None else "--sim-param spawn_x, spawn_y"
    return [f"{where}: {problem} on {map_yaml}"] if problem else []


def check_inputs(config: RunConfig) -> tuple[CheckedInputs | None, list[str]]:
    """Check every input of a run.

    Args:
        config: The configuration.

    Returns:
        ``(inputs, problems)``: ``inputs`` is None when a problem stops the run.
    """
    from sar_framework.engine.api import validate
    from sar_framework.engine.checking.initial_values import SetError, parse_settings
    from sar_framework.mission.params_file import read_params_file
    problems = _option_problems(config)
    overrides = {who: _entries(config, who, problems)
                 for who in ("sim", *config.app_params, "runner")}
    problems += [str(err) for err in check_values(overrides["sim"], SIM_PARAMETERS, {},
                                                  "--sim-param")]
    problems += _map_problems(config, overrides["sim"])
    spec = None
    apps: list[App] = []
    try:
        initial = parse_settings(config.sets)
    except SetError as err:
        problems.append(str(err))
        initial = {}
    if Path(config.tree).is_file():
        result = validate(config.tree, plugin_paths=config.plugin_paths, initial_values=initial)
        problems += [str(d) for d in result.diagnostics if d.severity == "error"]
        spec = result.spec
        try:
            # A tree with errors starts nothing; its parameters are checked against every
            # installed app's, so each mistake is still reported at once.
            apps = apps_for(spec, result.registry) if spec is not None else discover_apps()
        except AppError as err:
            problems.append(f"{config.tree}: {err}")
    file = params_file(config, apps)
    tables = node_parameters([*apps, *installed_apps()])
    for who in config.app_params:  # the apps' processes: known once the tree's apps are
        problems += [str(err) for err in check_values(overrides[who], tables.get(who, ()), {},
                                                      f"--{who}-param")]
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
    places = {name: xy for app in apps if app.places is not None
             for name, xy in app.places(values).items()}
    blocked = _blocked_areas(overrides["sim"], places, problems)
    _blocked_areas(overrides["sim"], places, problems, "phantom_obstacles")  # checked only
    for option, path in app_options(config, apps):
        problem = (option.check(path) if option.check is not None and Path(path).is_file()
                   else None)
        if problem:
            problems.append(problem)
    robots, robot_issues = robot_problems(config, values, overrides["sim"], apps)
    problems += robot_issues
    if problems or spec is None:
        return None, problems
    return CheckedInputs(spec, values, places, blocked, robots, tuple(apps), file,
                         frozenset(node.kind for node in spec.nodes())), problems
