"""Every parameter of a node, named and typed, checked in pure Python before it starts.

A :class:`ParamInfo` table per node (the runner's is :data:`RUNNER_PARAMETERS`) lets
``sar-tree run`` check the mission parameter file and each ``--X-param NAME:=VALUE`` before
any process starts: unknown names (with a did-you-mean), wrong types and impossible values
are all reported at once, each with its file, line and column when it has one.
"""

from __future__ import annotations

import fnmatch
import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any

from sar_framework.engine.diagnostics import did_you_mean
from sar_framework.mission.completion import COMPLETION_MODES
from sar_framework.mission.params_file import KeyLocation, ParamsError

_KIND_WORDS = {
    "float": "a number", "int": "an integer", "bool": "true or false", "str": "a string",
    "str[]": "a list of strings", "int[]": "a list of integers",
    "paths": "a string or a list of strings",
}


@dataclass(frozen=True)
class ParamInfo:
    """One parameter a node reads.

    Attributes:
        name: The dotted name; ``*`` stands for one name segment (``zones.*.x``).
        kind: ``float``, ``int``, ``bool``, ``str``, ``str[]``, ``int[]`` or ``paths``.
        doc: What it means, with its unit.
        positive: The value must be > 0.
        choices: The allowed values, when only some are.
    """

    name: str
    kind: str
    doc: str
    positive: bool = False
    choices: tuple[str, ...] = ()


RUNNER_PARAMETERS: tuple[ParamInfo, ...] = (
    ParamInfo("zone_order", "str[]", "the zone ids to visit, in order"),
    ParamInfo("zones.*.x", "float", "zone position x, m (map frame)"),
    ParamInfo("zones.*.y", "float", "zone position y, m (map frame)"),
    ParamInfo("zones.*.yaw", "float", "zone heading, rad"),
    ParamInfo("base_station.x", "float", "base station x, m"),
    ParamInfo("base_station.y", "float", "base station y, m"),
    ParamInfo("base_station.yaw", "float", "base station heading, rad"),
    ParamInfo("tick_rate_hz", "float", "tree ticks per second (ROS time)", positive=True),
    ParamInfo("completion", "str", "how the mission ends", choices=COMPLETION_MODES),
    ParamInfo("tree", "str", "the tree file"),
    ParamInfo("plugin_path", "paths", "extra plugin files, directories or modules"),
    ParamInfo("exit_on_completion", "bool", "end the runner once the mission is complete"),
    ParamInfo("print_tree", "bool", "log the tree on every status change"),
    ParamInfo("status_file", "str", "JSON status file ('' = none)"),
    ParamInfo("seed_amcl", "bool", "seed AMCL and wait for Nav2 before ticking"),
    ParamInfo("nav2_timeout_s", "float", "bound of the Nav2 start-up, s", positive=True),
    ParamInfo("setup_timeout_s", "float", "bound of the tree's setup, s", positive=True),
    ParamInfo("initial_pose.x", "float", "AMCL seed x, m"),
    ParamInfo("initial_pose.y", "float", "AMCL seed y, m"),
    ParamInfo("initial_pose.yaw", "float", "AMCL seed heading, rad"),
    ParamInfo("use_sim_time", "bool", "follow /clock"),
)
"""Every parameter ``sar_mission_runner`` reads (mission and runner settings)."""


def find_param(name: str, table: Iterable[ParamInfo]) -> ParamInfo | None:
    """The entry of ``table`` that ``name`` matches, or None."""
    for info in table:
        if info.name == name or ("*" in info.name and fnmatch.fnmatchcase(name, info.name)
                                 and name.count(".") == info.name.count(".")):
            return info
    return None


def value_problem(info: ParamInfo, value: Any) -> str | None:
    """What is wrong with ``value`` for ``info``, or None.

    Integers are accepted where a number is expected (as the nodes accept them).
    """
    kind = info.kind
    ok = {
        "float": isinstance(value, (int, float)) and not isinstance(value, bool),
        "int": isinstance(value, int) and not isinstance(value, bool),
        "bool": isinstance(value, bool),
        "str": isinstance(value, str),
        "str[]": isinstance(value, list) and all(isinstance(v, str) for v in value),
        "int[]": isinstance(value, list) and all(isinstance(v, int) and not isinstance(v, bool)
                                                 for v in value),
        "paths": isinstance(value, str) or (isinstance(value, list)
                                            and all(isinstance(v, str) for v in value)),
    }[kind]
    if not ok:
        return f"must be {_KIND_WORDS[kind]}, got {value!r}"
    if kind == "float" and not math.isfinite(value):
        return f"must be finite, got {value!r}"
    if info.positive and value <= 0:
        return f"must be > 0, got {value!r}"
    if info.choices and value not in info.choices:
        return (f"must be one of {', '.join(info.choices)}, got {value!r}"
                + did_you_mean(str(value), info.choices))
    return None


def check_values(values: Mapping[str, Any], table: Iterable[ParamInfo],
                 where: Mapping[str, KeyLocation], source: str) -> list[ParamsError]:
    """Check names and types of ``values`` against ``table``.

    Args:
        values: Dotted name -> value.
        table: The node's parameters.
        where: Where each name is set, when known.
        source: Names the origin of a value without a location.

    Returns:
        One error per unknown name or bad value.
    """
    table = tuple(table)
    names = [i.name.replace("*", "<id>") for i in table]
    problems = []
    for name, value in values.items():
        info = find_param(name, table)
        problem = (value_problem(info, value) if info is not None
                   else "unknown parameter" + did_you_mean(name, names))
        if problem is not None:
            problems.append(located(name, problem, where, source))
    return problems


def located(name: str, problem: str, where: Mapping[str, KeyLocation],
            source: str) -> ParamsError:
    """An error about ``name``, at its file, line and column when known."""
    at = where.get(name)
    if at is None:
        return ParamsError(source, name, problem)
    return ParamsError(at.file, name, problem, at.line, at.col)


def mission_problems(values: Mapping[str, Any], where: Mapping[str, KeyLocation],
                     source: str) -> list[ParamsError]:
    """What the runner would reject about the mission itself (zones and their order).

    Args:
        values: The runner's parameters (file values, then overrides).
        where: Where each name is set.
        source: Names the parameter file.

    Returns:
        Every problem: ``zone_order`` missing, empty, repeated or naming a zone without
        coordinates.
    """
    order = values.get("zone_order")
    if order is None:
        return [ParamsError(source, "zone_order", "missing (list the zone ids to visit, "
                            "in order)")]
    if not isinstance(order, list) or not all(isinstance(z, str) for z in order):
        return []  # the type check said so
    problems = []
    seen: set[str] = set()
    for zone_id in order:
        if not zone_id:
            problems.append(located("zone_order", "an empty zone id", where, source))
        elif zone_id in seen:
            problems.append(located("zone_order", f"{zone_id} is listed twice", where, source))
        seen.add(zone_id)
        for axis in ("x", "y", "yaw"):
            if zone_id and f"zones.{zone_id}.{axis}" not in values:
                defined = sorted({k.split(".")[1] for k in values if k.startswith("zones.")})
                problems.append(located(
                    "zone_order", f"zones.{zone_id}.{axis} is missing ({zone_id} is in "
                    "zone_order)" + did_you_mean(zone_id, defined), where, source))
                break
    return problems


def zone_positions(values: Mapping[str, Any]) -> dict[str, tuple[float, float]]:
    """Zone id -> ``(x, y)`` for every zone with both coordinates set as numbers."""
    zones: dict[str, tuple[float, float]] = {}
    for name, value in values.items():
        parts = name.split(".")
        if len(parts) == 3 and parts[0] == "zones" and parts[2] == "x":
            y = values.get(f"zones.{parts[1]}.y")
            if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in (value, y)):
                zones[parts[1]] = (float(value), float(y))
    return zones
