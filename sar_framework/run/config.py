"""Configuration of ``sar-tree run``: its options, the checks of its inputs, its children.

Everything here happens before a process starts: :func:`configure` declares the command
line, :func:`check_config` checks every input, :func:`mission_settings` says what the
mission starts (:mod:`sar_framework.mission.processes`, the description the launch file
shares), :func:`child_specs` turns it into command lines and :func:`ros_environment` gives
their environment.
"""

from __future__ import annotations

import argparse
import os
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from sar_framework.mission.processes import (
    MissionSettings,
    ParamValue,
    mission_processes,
    ros_arguments,
)
from sar_framework.run.inputs import CheckedInputs, check_inputs, parse_entry
from sar_framework.sim.params import SPEED

DEFAULT_DOMAIN_ID = 42
"""``ROS_DOMAIN_ID`` when the environment sets none (the Makefile's value too)."""
DEFAULT_TIMEOUT_S = 300.0
DEFAULT_PARAMS = "config/mission_params.yaml"
DEFAULT_REPORT_DIR = "reports/latest"



class RunUsageError(Exception):
    """Bad input found before anything was started: printed, exit code 2."""


@dataclass(frozen=True)
class ChildSpec:
    """One process of the mission as ``sar-tree run`` starts it.

    Attributes:
        label: Short name used in progress lines and for the log file (``runner.log``).
        module: The Python module run with ``-m``.
        ros_args: Everything after ``--ros-args``.
        executable: The console script of the same program (what the launch file starts).
    """

    label: str
    module: str
    ros_args: tuple[str, ...]
    executable: str = ""


@dataclass
class RunConfig:
    """What ``sar-tree run`` was asked to do.

    Attributes:
        tree: The tree file.
        params: The mission parameter file.
        survivors: The detect server's survivor table, or None for its default.
        sim: Start the embedded simulator (else real Nav2 must be running).
        speed: The simulator's speed factor.
        report_dir: Where logs and the report go.
        timeout_s: Wall-clock bound of the mission.
        keep_alive: Stay up after the mission until Ctrl-C.
        verbose: Print every child log line, not only progress, warnings and errors.
        detect_server: Start the detect server.
        report_server: Start the report server.
        sim_params: Extra ``NAME:=VALUE`` for the simulator.
        detect_params: Extra ``NAME:=VALUE`` for the detect server.
        report_params: Extra ``NAME:=VALUE`` for the report server.
        runner_params: Extra ``NAME:=VALUE`` for the runner.
        plugin_paths: Extra plugin locations for the runner.
        record: The MCAP file to record the mission into, or None.
        watch: Show the tree live (``sar-tree watch``) instead of progress lines.
    """

    tree: str
    params: str = DEFAULT_PARAMS
    survivors: str | None = None
    sim: bool = True
    speed: float = SPEED.default
    report_dir: str = DEFAULT_REPORT_DIR
    timeout_s: float = DEFAULT_TIMEOUT_S
    keep_alive: bool = False
    verbose: bool = False
    detect_server: bool = True
    report_server: bool = True
    sim_params: list[str] = field(default_factory=list)
    detect_params: list[str] = field(default_factory=list)
    report_params: list[str] = field(default_factory=list)
    runner_params: list[str] = field(default_factory=list)
    plugin_paths: list[str] = field(default_factory=list)
    record: str | None = None
    watch: bool = False


# -- command line -------------------------------------------------------------------------
def configure(parser: argparse.ArgumentParser) -> None:
    """Add ``sar-tree run``'s arguments to ``parser``.

    Args:
        parser: The subcommand's parser.
    """
    from sar_framework.mission.completion import COMPLETION_HELP

    parser.epilog = (COMPLETION_HELP + " Faults to inject (--sim-param, --detect-param, "
                     "--report-param NAME:=VALUE): see `sar-tree faults`.")
    parser.add_argument("tree", metavar="TREE", help="the tree file")
    parser.add_argument("--params", default=DEFAULT_PARAMS, metavar="FILE",
                        help=f"mission parameter file (default: {DEFAULT_PARAMS})")
    parser.add_argument("--survivors", metavar="FILE",
                        help="survivor table for the detect server "
                        "(default: config/survivors.yaml)")
    sim = parser.add_mutually_exclusive_group()
    sim.add_argument("--sim", dest="sim", action="store_true", default=True,
                     help="run the embedded simulator (default)")
    sim.add_argument("--no-sim", dest="sim", action="store_false",
                     help="do not start the simulator: real Nav2 must be running")
    parser.add_argument("--speed", type=float, default=SPEED.default, metavar="X",
                        help=f"the simulator's speed: {SPEED.description.split(';')[0]}, "
                        f"{SPEED.bounds()} (default: {SPEED.default:g})")
    parser.add_argument("--report-dir", default=DEFAULT_REPORT_DIR, metavar="DIR",
                        help=f"logs and mission report (default: {DEFAULT_REPORT_DIR})")
    parser.add_argument("--timeout", type=float, default=DEFAULT_TIMEOUT_S, metavar="S",
                        help=f"give up after S wall seconds (default: {DEFAULT_TIMEOUT_S:g})")
    parser.add_argument("--keep-alive", action="store_true",
                        help="stay up after the mission (TF, services) until Ctrl-C")
    parser.add_argument("-v", "--verbose", action="store_true",
                        help="print every log line of every process")
    parser.add_argument("--no-detect-server", dest="detect_server", action="store_false",
                        help="do not start the detect server (fault injection)")
    parser.add_argument("--no-report-server", dest="report_server", action="store_false",
                        help="do not start the report server (fault injection)")
    for who in ("sim", "detect", "report", "runner"):
        parser.add_argument(f"--{who}-param", dest=f"{who}_params", action="append",
                            default=[], metavar="NAME:=VALUE",
                            help=f"extra ROS parameter for the {who} (repeatable; "
                            "docs/parameters.md lists each node's)")
    parser.add_argument("--plugin-path", action="append", default=[], metavar="P",
                        help="extra plugin .py file, directory or module name (repeatable)")
    parser.add_argument("--record", metavar="FILE.mcap",
                        help="record the mission into a rosbag2-compatible MCAP file")
    parser.add_argument("--watch", action="store_true",
                        help="show the tree live (sar-tree watch) instead of progress lines")


def config_from_args(args: argparse.Namespace) -> RunConfig:
    """Turn parsed arguments into a :class:`RunConfig`.

    Args:
        args: The namespace :func:`configure`'s arguments produced.

    Returns:
        The configuration (not yet checked; see :func:`check_config`).
    """
    return RunConfig(
        tree=args.tree, params=args.params, survivors=args.survivors, sim=args.sim,
        speed=args.speed, report_dir=args.report_dir, timeout_s=args.timeout,
        keep_alive=args.keep_alive, verbose=args.verbose,
        detect_server=args.detect_server, report_server=args.report_server,
        sim_params=list(args.sim_params), detect_params=list(args.detect_params),
        report_params=list(args.report_params), runner_params=list(args.runner_params),
        plugin_paths=list(args.plugin_path), record=args.record,
        watch=args.watch,
    )


def check_config(config: RunConfig) -> CheckedInputs:
    """Check every input before any process starts (:mod:`sar_framework.run.inputs`).

    Args:
        config: The configuration.

    Returns:
        What the checks found (the tree's spec, the runner's parameters, the zones).

    Raises:
        RunUsageError: One problem or more; the message holds every one, a line each.
    """
    inputs, problems = check_inputs(config)
    if inputs is None:
        raise RunUsageError("\n".join(problems) or f"cannot use {config.tree}")
    return inputs


def blocked_zone_entry(entry: str, zones: dict[str, tuple[float, float]]) -> str:
    """A ``blocked_zones`` entry with a mission zone name replaced by ``x:y:radius``.

    Args:
        entry: ``zone_b``, ``zone_b:0.8``, a world marker name or ``x:y:radius``.
        zones: Mission zone id -> ``(x, y)``.
    """
    from sar_framework.sim.params import DEFAULT_NAMED_RADIUS

    name, _, radius = entry.strip().partition(":")
    if name not in zones:
        return entry
    x, y = zones[name]
    return f"{x:g}:{y:g}:{radius or f'{DEFAULT_NAMED_RADIUS:g}'}"


def entry_values(entries: Sequence[str],
                 zones: dict[str, tuple[float, float]] | None = None) -> dict[str, ParamValue]:
    """``NAME:=VALUE`` entries as typed values, read as rcl reads them (the last one wins).

    Mission zone names in a ``blocked_zones`` list become ``x:y:radius`` (the simulator
    knows its world's markers, not the mission's zones).

    Args:
        entries: ``--sim-param`` (or ``--detect-param``...) entries, already checked.
        zones: Mission zone id -> ``(x, y)``.
    """
    values: dict[str, ParamValue] = {}
    for entry in entries:
        parsed = parse_entry(entry)
        if parsed is None:
            continue  # check_config reported it; nothing starts with it
        name, value = parsed
        if name == "blocked_zones" and isinstance(value, list):
            value = [blocked_zone_entry(str(e), zones or {}) for e in value]
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
                     zones: dict[str, tuple[float, float]] | None = None) -> MissionSettings:
    """What the mission starts, from ``sar-tree run``'s options.

    The trace, status and report files go into the report folder; the servers and the
    runner follow ``/clock`` only with the simulator; the runner stays up with
    ``--keep-alive``; ``--sim-param`` and the like are set last.

    Args:
        config: The configuration.
        report_dir: The report folder.
        zones: Mission zone id -> ``(x, y)`` (``blocked_zones`` may name them).
    """
    return MissionSettings(
        tree=config.tree, params_file=config.params, use_sim_time=config.sim,
        simulator=config.sim, speed=config.speed, trace_file=str(report_dir / "trace.jsonl"),
        detect_server=config.detect_server, survivors_file=config.survivors or "",
        report_server=config.report_server, report_file=str(report_dir / "reports.jsonl"),
        exit_on_completion=not config.keep_alive,
        status_file=str(report_dir / "status.json"),
        plugin_paths=tuple(config.plugin_paths), record=config.record or "",
        extra={"sim": entry_values(config.sim_params, zones),
               "detect": entry_values(config.detect_params),
               "report": entry_values(config.report_params),
               "runner": entry_values(config.runner_params)})


def child_specs(config: RunConfig, report_dir: Path,
                zones: dict[str, tuple[float, float]] | None = None) -> list[ChildSpec]:
    """The processes of a mission, in start order (the runner last), as command lines.

    Args:
        config: The configuration.
        report_dir: The report folder (status, trace and report files go there).
        zones: Mission zone id -> ``(x, y)`` (``blocked_zones`` may name them).

    Returns:
        One spec per child process (:func:`~sar_framework.mission.processes.mission_processes`
        of :func:`mission_settings`).
    """
    return [ChildSpec(p.label, p.module, tuple(ros_arguments(p)), p.executable)
            for p in mission_processes(mission_settings(config, report_dir, zones))]
