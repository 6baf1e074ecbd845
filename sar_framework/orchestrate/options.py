"""The options of ``sar-tree run``: its command line and :class:`RunConfig` (no checks).

:func:`configure` declares the command line, :func:`config_from_args` reads it into a
:class:`RunConfig`; :mod:`.inputs` checks it and :mod:`.config` turns it into children.
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass, field
from pathlib import Path

from sar_framework.app import installed_apps
from sar_framework.sim.params import DEFAULT_MAP_YAML, SPEED, parse_pose, pose_entries

DEFAULT_DOMAIN_ID = 42
"""``ROS_DOMAIN_ID`` when the environment sets none (the Makefile's value too)."""
DEFAULT_TIMEOUT_S = 300.0
DEFAULT_REPORT_DIR = "reports/latest"


class RunUsageError(Exception):
    """Bad input found before anything was started: printed, exit code 2."""


@dataclass
class RunConfig:
    """What ``sar-tree run`` was asked to do.

    Attributes:
        tree: The tree file.
        params: The mission parameter file; None: the tree's app's default (none for a tree
            that uses no app), set by :func:`~sar_framework.orchestrate.config.check_config`.
        sim: Start the embedded simulator (else real Nav2 must be running).
        speed: The simulator's speed factor.
        report_dir: Where logs and the report go.
        timeout_s: Wall-clock bound of the mission.
        sim_timeout_s: Bound of the tree's ticking on its ROS clock, or None.
        keep_alive: Stay up after the mission until Ctrl-C.
        verbose: Print every child log line, not only progress, warnings and errors.
        sim_params: Extra ``NAME:=VALUE`` for the simulator.
        runner_params: Extra ``NAME:=VALUE`` for the runner.
        app_params: An app's process label -> extra ``NAME:=VALUE`` for it
            (``--detect-param``).
        app_options: An app's file options given, by flag (``--table`` -> its file).
        disabled: Labels of the apps' processes not to start (``--no-detect-server``).
        plugin_paths: Extra plugin locations for the runner.
        record: The MCAP file to record the mission into, or None.
        watch: Show the tree live (``sar-tree watch``) instead of progress lines.
        reload: Reload the tree when its file changes (the runner's ``watch_tree``).
        robots: Run a fleet of this many robots near the base (``--robots N``), or None.
        fleet: Run the fleet of this fleet file (``--fleet FILE``), or None.
        map: The simulator's map (``--map``, a map_server yaml), or None: its default.
        spawn: Where the robot starts, ``(x, y, yaw)`` (``--spawn``), or None: the
            simulator's default.
        sets: ``NAME=VALUE`` initial values of entries the tree declares (``--set``).
    """

    tree: str
    params: str | None = None
    sim: bool = True
    speed: float = SPEED.default
    report_dir: str = DEFAULT_REPORT_DIR
    timeout_s: float = DEFAULT_TIMEOUT_S
    sim_timeout_s: float | None = None
    keep_alive: bool = False
    verbose: bool = False
    sim_params: list[str] = field(default_factory=list)
    runner_params: list[str] = field(default_factory=list)
    app_params: dict[str, list[str]] = field(default_factory=dict)
    app_options: dict[str, str] = field(default_factory=dict)
    disabled: list[str] = field(default_factory=list)
    plugin_paths: list[str] = field(default_factory=list)
    record: str | None = None
    watch: bool = False
    reload: bool = False
    robots: int | None = None
    fleet: str | None = None
    map: str | None = None
    spawn: tuple[float, float, float] | None = None
    sets: list[str] = field(default_factory=list)

    @property
    def names_robots(self) -> bool:
        """Whether the run names its robots (``--robots`` or ``--fleet``)."""
        return self.robots is not None or self.fleet is not None

    @property
    def sim_entries(self) -> list[str]:
        """The simulator's ``NAME:=VALUE`` entries: ``--map``, ``--spawn``, then ``--sim-param``."""
        entries = [f"map_yaml:={str(Path(self.map).absolute())!r}"] if self.map else []
        entries += pose_entries(self.spawn) if self.spawn is not None else []
        return entries + self.sim_params


# -- command line -------------------------------------------------------------------------
def _dest(flag: str) -> str:
    return "app_option_" + flag.lstrip("-").replace("-", "_")


def _pose(text: str) -> tuple[float, float, float]:
    try:
        return parse_pose(text)
    except ValueError as err:
        raise argparse.ArgumentTypeError(str(err)) from None


def configure(parser: argparse.ArgumentParser) -> None:
    """Add ``sar-tree run``'s arguments to ``parser``, the installed apps' with the core's.

    Each app process adds ``--LABEL-param`` (and its ``off_flag``); each app option its flag.

    Args:
        parser: The subcommand's parser.
    """
    from sar_framework.mission.completion import COMPLETION_HELP

    apps = installed_apps()
    kinds = [kind for app in apps for kind in app.process_kinds]
    labels = ["sim", *(kind.label for kind in kinds)]
    parser.epilog = (COMPLETION_HELP + " Faults to inject ("
                     + ", ".join(f"--{label}-param" for label in labels)
                     + " NAME:=VALUE): see `sar-tree faults`.")
    parser.add_argument("tree", metavar="TREE", help="the tree file")
    parser.add_argument("--params", metavar="FILE",
                        help="mission parameter file (default: the tree's app's, e.g. "
                        "config/mission_params.yaml for search and rescue; none for a tree "
                        "that uses no app)")
    for option in (option for app in apps for option in app.options):
        parser.add_argument(option.flag, dest=_dest(option.flag), metavar="FILE",
                            help=option.help)
    sim = parser.add_mutually_exclusive_group()
    sim.add_argument("--sim", dest="sim", action="store_true", default=True,
                     help="run the embedded simulator (default)")
    sim.add_argument("--no-sim", dest="sim", action="store_false",
                     help="do not start the simulator: real Nav2 must be running")
    parser.add_argument("--map", metavar="FILE.yaml",
                        help="the simulator's map: a nav2 map_server yaml as map_saver writes "
                        "it (image, resolution, origin, negate, occupied_thresh, free_thresh, "
                        f"mode; default: {DEFAULT_MAP_YAML.parent.name}/{DEFAULT_MAP_YAML.name})")
    parser.add_argument("--spawn", type=_pose, metavar="X,Y[,YAW]",
                        help="where the robot starts on the map: metres, metres, radians "
                        "(default: 0,0,0)")
    parser.add_argument("--speed", type=float, default=SPEED.default, metavar="X",
                        help=f"the simulator's speed: {SPEED.description.split(';')[0]}, "
                        f"{SPEED.bounds()} (default: {SPEED.default:g})")
    parser.add_argument("--report-dir", default=DEFAULT_REPORT_DIR, metavar="DIR",
                        help=f"logs and mission report (default: {DEFAULT_REPORT_DIR})")
    parser.add_argument("--timeout", type=float, default=DEFAULT_TIMEOUT_S, metavar="S",
                        help=f"give up after S wall seconds (default: {DEFAULT_TIMEOUT_S:g})")
    parser.add_argument("--sim-timeout", type=float, metavar="S",
                        help="give up once the tree has ticked S seconds on its ROS clock "
                        "(simulated seconds with the simulator; exit code and message as "
                        "--timeout; default: no bound)")
    parser.add_argument("--keep-alive", action="store_true",
                        help="stay up after the mission (TF, services) until Ctrl-C")
    parser.add_argument("-v", "--verbose", action="store_true",
                        help="print every log line of every process")
    for kind in kinds:
        if kind.off_flag:
            parser.add_argument(kind.off_flag, dest="disabled", action="append_const",
                                const=kind.label, help=kind.off_help)
    for who in (*labels, "runner"):
        parser.add_argument(f"--{who}-param", dest=f"{who}_params", action="append",
                            default=[], metavar="NAME:=VALUE",
                            help=f"extra ROS parameter for the {who} (repeatable; "
                            "docs/reference/parameters.md lists each node's)")
    parser.add_argument("--plugin-path", action="append", default=[], metavar="P",
                        help="extra plugin .py file, directory or module name (repeatable)")
    parser.add_argument("--set", dest="sets", action="append", default=[],
                        metavar="NAME=VALUE",
                        help="the initial value of an entry the tree declares under "
                        "'blackboard:', checked against its type (repeatable)")
    parser.add_argument("--record", metavar="FILE.mcap",
                        help="record the mission into a rosbag2-compatible MCAP file")
    parser.add_argument("--watch", action="store_true",
                        help="show the tree live (sar-tree watch) instead of progress lines")
    parser.add_argument("--reload", action="store_true",
                        help="swap the tree in between ticks whenever its file or an include "
                        "changes; an invalid edit is refused (docs/how-to/hot-reload.md)")
    parser.add_argument("--robots", type=int, metavar="N",
                        help="run N named robots (a fleet), each with its runner and its "
                        "apps' per-robot processes in /robot1... (docs/how-to/fleet.md)")
    parser.add_argument("--fleet", metavar="FILE",
                        help="run the fleet of this fleet file (names and spawn poses)")


def config_from_args(args: argparse.Namespace) -> RunConfig:
    """Turn parsed arguments into a :class:`RunConfig`.

    Args:
        args: The namespace :func:`configure`'s arguments produced.

    Returns:
        The configuration (not yet checked; see :func:`check_config`).
    """
    apps = installed_apps()
    labels = [kind.label for app in apps for kind in app.process_kinds]
    flags = [option.flag for app in apps for option in app.options]
    return RunConfig(
        tree=args.tree, params=args.params, sim=args.sim,
        speed=args.speed, report_dir=args.report_dir, timeout_s=args.timeout,
        sim_timeout_s=args.sim_timeout,
        keep_alive=args.keep_alive, verbose=args.verbose,
        sim_params=list(args.sim_params), runner_params=list(args.runner_params),
        app_params={label: list(getattr(args, f"{label}_params")) for label in labels
                    if getattr(args, f"{label}_params")},
        app_options={flag: getattr(args, _dest(flag)) for flag in flags
                     if getattr(args, _dest(flag)) is not None},
        disabled=list(getattr(args, "disabled", None) or []),
        plugin_paths=list(args.plugin_path), record=args.record,
        watch=args.watch, reload=args.reload, robots=args.robots, fleet=args.fleet,
        map=args.map, spawn=args.spawn,
        sets=list(args.sets),
    )
