"""The children of ``sar-tree run``: its inputs checked, what the mission starts, how.

Everything here happens before a process starts: :func:`check_config` checks every input
(:mod:`.inputs`), :func:`mission_settings` says what the mission starts
(:mod:`sar_framework.mission.processes`, the description the launch file shares),
:func:`child_specs` turns it into command lines and :func:`ros_environment` gives their
environment. The options themselves are :mod:`.options`.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from sar_framework.app import App
from sar_framework.mission.processes import (
    ONE_ROBOT,
    MissionSettings,
    ParamValue,
    Robot,
    mission_processes,
    ros_arguments,
)
from sar_framework.orchestrate.inputs import CheckedInputs, app_options, check_inputs, parse_entry
from sar_framework.orchestrate.options import DEFAULT_DOMAIN_ID, RunConfig, RunUsageError
from sar_framework.orchestrate.robots import fleet_file


@dataclass(frozen=True)
class ChildSpec:
    """One process of the mission as ``sar-tree run`` starts it.

    Attributes:
        label: Short name used in progress lines and for the log file (``runner.log``).
        module: The Python module run with ``-m``.
        ros_args: Everything after ``--ros-args``.
        executable: The console script of the same program (what the launch file starts).
        python_path: Folders the module is imported from, before ``PYTHONPATH``.
    """

    label: str
    module: str
    ros_args: tuple[str, ...]
    executable: str = ""
    python_path: tuple[str, ...] = ()


def check_config(config: RunConfig) -> CheckedInputs:
    """Check every input before any process starts (:mod:`sar_framework.orchestrate.inputs`).

    Args:
        config: The configuration.

    Returns:
        What the checks found (the tree's spec, its apps, the runner's parameters, the
        places); ``config.params`` is set to the parameter file used ("" for none).

    Raises:
        RunUsageError: One problem or more; the message holds every one, a line each.
    """
    inputs, problems = check_inputs(config)
    if inputs is None:
        raise RunUsageError("\n".join(problems) or f"cannot use {config.tree}")
    config.params = inputs.params_file
    return inputs


def blocked_area_entry(entry: str, places: dict[str, tuple[float, float]]) -> str:
    """A ``blocked_areas`` entry with an app's place name replaced by ``x:y:radius``.

    Args:
        entry: a place (``shelf_nw``, ``shelf_nw:0.8``), a world marker name or ``x:y:radius``.
        places: The apps' place name -> ``(x, y)``.
    """
    from sar_framework.sim.params import DEFAULT_NAMED_RADIUS

    name, _, radius = entry.strip().partition(":")
    if name not in places:
        return entry
    x, y = places[name]
    return f"{x:g}:{y:g}:{radius or f'{DEFAULT_NAMED_RADIUS:g}'}"


def entry_values(entries: Sequence[str],
                 places: dict[str, tuple[float, float]] | None = None) -> dict[str, ParamValue]:
    """``NAME:=VALUE`` entries as typed values, read as rcl reads them (the last one wins).

    The apps' place names in a ``blocked_areas`` or ``phantom_obstacles`` list become
    ``x:y:radius`` (the simulator knows the map, not the apps' places).

    Args:
        entries: ``--sim-param`` (or ``--detect-param``...) entries, already checked.
        places: The apps' place name -> ``(x, y)``.
    """
    values: dict[str, ParamValue] = {}
    for entry in entries:
        parsed = parse_entry(entry)
        if parsed is None:
            continue  # check_config reported it; nothing starts with it
        name, value = parsed
        if name in ("blocked_areas", "phantom_obstacles") and isinstance(value, list):
            value = [blocked_area_entry(str(e), places or {}) for e in value]
        values[name] = value
    return values


def ros_environment(base: dict[str, str] | None = None, *,
                    log_dir: Path | None = None) -> dict[str, str]:
    """The environment every child runs with.

    Loopback-only discovery, the caller's ``ROS_DOMAIN_ID`` or :data:`DEFAULT_DOMAIN_ID`,
    unbuffered, uncoloured output.

    Args:
        base: The environment to start from (``os.environ`` by default).
        log_dir: Where rcl writes its log files (``ROS_LOG_DIR``), if given.

    Returns:
        A new environment mapping.
    """
    env = dict(os.environ if base is None else base)
    env["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
    env.pop("ROS_LOCALHOST_ONLY", None)
    if not env.get("ROS_DOMAIN_ID", "").strip():
        env["ROS_DOMAIN_ID"] = str(DEFAULT_DOMAIN_ID)
    env.setdefault("RMW_IMPLEMENTATION", "rmw_fastrtps_cpp")
    env["PYTHONUNBUFFERED"] = "1"
    env["RCUTILS_COLORIZED_OUTPUT"] = "0"
    if log_dir is not None:
        env["ROS_LOG_DIR"] = str(log_dir)
    return env


def mission_settings(config: RunConfig, report_dir: Path,
                     places: dict[str, tuple[float, float]] | None = None,
                     apps: Sequence[App] = (), *, robots: Sequence[Robot] = ONE_ROBOT,
                     node_kinds: frozenset[str] = frozenset()) -> MissionSettings:
    """What the mission starts, from ``sar-tree run``'s options.

    The trace, status and report files go into the report folder; the servers and the
    runner follow ``/clock`` only with the simulator; the runner stays up with
    ``--keep-alive``; ``--sim-param`` and the like are set last.

    Args:
        config: The configuration.
        report_dir: The report folder.
        places: The apps' place name -> ``(x, y)`` (``blocked_areas`` may name them).
        apps: The tree's apps (their file options set their processes' files).
        robots: The robots (named ones read the fleet file, ``--fleet``'s or the folder's).
        node_kinds: The tree's node kinds.
    """
    extra: dict[str, dict[str, Any]] = {}
    for option, path in app_options(config, apps):
        extra.setdefault(option.process, {})[option.parameter] = path
    for label, entries in config.app_params.items():
        extra[label] = {**extra.get(label, {}), **entry_values(entries)}
    return MissionSettings(
        tree=config.tree, params_file=config.params or "", use_sim_time=config.sim,
        simulator=config.sim, speed=config.speed, trace_file=str(report_dir / "trace.jsonl"),
        run_folder=str(report_dir), disabled=frozenset(config.disabled),
        exit_on_completion=not config.keep_alive, watch_tree=config.reload,
        status_file=str(report_dir / "status.json"),
        plugin_paths=tuple(config.plugin_paths), record=config.record or "",
        extra={**extra, "sim": entry_values(config.sim_entries, places),
               "runner": {**({} if config.sim_timeout_s is None
                             else {"sim_timeout_s": config.sim_timeout_s}),
                          **({"set": list(config.sets)} if config.sets else {}),
                          **entry_values(config.runner_params)}},
        robots=tuple(robots), node_kinds=node_kinds,
        fleet_file=str(fleet_file(config, report_dir)) if any(r.name for r in robots) else "")


def child_specs(config: RunConfig, report_dir: Path,
                places: dict[str, tuple[float, float]] | None = None, *,
                apps: Sequence[App] = (), robots: Sequence[Robot] = ONE_ROBOT,
                node_kinds: frozenset[str] = frozenset()) -> list[ChildSpec]:
    """The processes of a mission, in start order (the runners last), as command lines.

    Args:
        config: The configuration.
        report_dir: The report folder (status, trace and report files go there; a named
            robot's into ``report_dir/<name>/``).
        places: The apps' place name -> ``(x, y)`` (``blocked_areas`` may name them).
        apps: The tree's apps (their processes start before the runners).
        robots: The robots.
        node_kinds: The tree's node kinds (which of the apps' processes start).

    Returns:
        One spec per child process (:func:`~sar_framework.mission.processes.mission_processes`
        of :func:`mission_settings`), labelled ``robot1/runner`` in a namespace.
    """
    settings = mission_settings(config, report_dir, places, apps, robots=robots,
                                node_kinds=node_kinds)
    return [ChildSpec(p.name, p.module, tuple(ros_arguments(p)), p.executable, p.python_path)
            for p in mission_processes(settings, apps)]
