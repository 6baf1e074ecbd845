"""``sar-tree run``: the whole mission from one command.

Starts, as child processes of this one (the way the launch file composes them): the
embedded simulator (unless ``--no-sim``), the detect and report servers, and the tree
runner; prints the mission's progress; stops everything in order; writes the mission
report (:mod:`sar_framework.report`) into the report folder, beside every child's log.

Exit codes: 0 the root reached SUCCESS, 1 FAILURE, a timeout or a failed start-up, 2 bad
input (missing tree, a tree or parameter file with errors, a bad option), 130 interrupted.

Processes: each child runs ``sys.executable -m <module> --ros-args ...`` in a session of
its own, so a Ctrl-C in the terminal reaches only this process, which then stops the
runner first (its running leaves cancel their goals while the simulator still serves),
then the servers and the simulator, and kills whatever is still alive after a bound. A
child also receives SIGTERM if this process dies without cleaning up (Linux
``PR_SET_PDEATHSIG``), so no child outlives it.
"""

from __future__ import annotations

import argparse
import contextlib
import ctypes
import ctypes.util
import json
import os
import re
import signal
import subprocess
import sys
import threading
import time
from collections import Counter
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from types import FrameType
from typing import IO, Any

EXIT_OK = 0
EXIT_FAILURE = 1
EXIT_USAGE = 2
EXIT_INTERRUPTED = 130

DEFAULT_DOMAIN_ID = 42
"""``ROS_DOMAIN_ID`` when the environment sets none (the Makefile's value too)."""
DEFAULT_SPEED = 20.0
"""Simulated seconds per wall second (see ``benchmarks/bench_mission.py``)."""
DEFAULT_TIMEOUT_S = 300.0
DEFAULT_PARAMS = "config/mission_params.yaml"
DEFAULT_REPORT_DIR = "reports/latest"
RUNNER_STOP_S = 1.2
"""Wall seconds the runner gets to cancel its goals and exit after SIGINT."""
OTHERS_STOP_S = 0.6
"""Wall seconds the servers and the simulator get after SIGINT before SIGKILL."""
POLL_S = 0.05

_ROS_LINE = re.compile(r"^\[(DEBUG|INFO|WARN|ERROR|FATAL)\] \[[0-9.]+\] \[([^\]]+)\]: (.*)$")
_PROGRESS = re.compile(
    r"^(--- Zone \d+/\d+: |Reached |Detection request for |Report received: |"
    r"Report refused: |No survivor found at |All zones visited|Mission complete\.|"
    r"Mission failed|Broadcast static TF )"
)
_GOAL_ENDED = re.compile(r"^Goal \d+ (canceled|aborted|succeeded)")
_NAME_VALUE = re.compile(r"^[A-Za-z_][A-Za-z0-9_.]*:=.*$")


class RunUsageError(Exception):
    """Bad input found before anything was started: printed, exit code 2."""


@dataclass(frozen=True)
class ChildSpec:
    """One process of the mission.

    Attributes:
        label: Short name used in progress lines and for the log file (``runner.log``).
        module: The Python module run with ``-m``.
        ros_args: Everything after ``--ros-args``.
    """

    label: str
    module: str
    ros_args: tuple[str, ...]


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
    """

    tree: str
    params: str = DEFAULT_PARAMS
    survivors: str | None = None
    sim: bool = True
    speed: float = DEFAULT_SPEED
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


# -- command line -------------------------------------------------------------------------
def configure(parser: argparse.ArgumentParser) -> None:
    """Add ``sar-tree run``'s arguments to ``parser``.

    Args:
        parser: The subcommand's parser.
    """
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
    parser.add_argument("--speed", type=float, default=DEFAULT_SPEED, metavar="X",
                        help=f"simulated seconds per wall second (default: {DEFAULT_SPEED:g})")
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
                            help=f"extra ROS parameter for the {who} (repeatable)")
    parser.add_argument("--plugin-path", action="append", default=[], metavar="P",
                        help="extra plugin .py file, directory or module name (repeatable)")


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
        plugin_paths=list(args.plugin_path),
    )


def check_config(config: RunConfig) -> Any:
    """Check every input before any process starts.

    Args:
        config: The configuration.

    Returns:
        The tree's :class:`~sar_framework.engine.spec.TreeSpec`.

    Raises:
        RunUsageError: A file is missing or invalid, or an option is out of range; the
            message is ready to print (diagnostics GCC style, one per line).
    """
    from sar_framework.engine.api import validate
    from sar_framework.mission.params_file import ParamsError, check_params_file

    for label, path in (("tree", config.tree), ("parameter file", config.params),
                        ("survivor table", config.survivors)):
        if path is not None and not Path(path).is_file():
            raise RunUsageError(f"{label} not found: '{path}'")
    if not (config.speed > 0 and config.speed < 1e6):
        raise RunUsageError(f"--speed must be a positive number, got {config.speed:g}")
    if not config.timeout_s > 0:
        raise RunUsageError(f"--timeout must be positive, got {config.timeout_s:g}")
    for who in ("sim", "detect", "report", "runner"):
        for entry in getattr(config, f"{who}_params"):
            if not _NAME_VALUE.match(entry):
                raise RunUsageError(f"--{who}-param {entry!r}: expected NAME:=VALUE")
    result = validate(config.tree, plugin_paths=config.plugin_paths)
    if result.spec is None:
        lines = [str(d) for d in result.diagnostics]
        errors = sum(1 for d in result.diagnostics if d.severity == "error")
        lines.append(f"{errors} error{'s' if errors != 1 else ''} in {config.tree}")
        raise RunUsageError("\n".join(lines))
    try:
        check_params_file(config.params)
    except ParamsError as err:
        raise RunUsageError(str(err)) from None
    return result.spec


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


def child_specs(config: RunConfig, report_dir: Path) -> list[ChildSpec]:
    """The processes of a mission, in start order (the runner last).

    Args:
        config: The configuration.
        report_dir: The report folder (status, trace and report files go there).

    Returns:
        One spec per child process.
    """
    sim_time = ("-p", f"use_sim_time:={'true' if config.sim else 'false'}")

    def params(entries: Sequence[str]) -> tuple[str, ...]:
        return tuple(a for entry in entries for a in ("-p", entry))

    specs: list[ChildSpec] = []
    if config.sim:
        specs.append(ChildSpec("sim", "sar_framework.sim", (
            "-p", f"speed:={config.speed:g}",
            "-p", f"trace_file:={report_dir / 'trace.jsonl'}",
            *params(config.sim_params))))
    if config.detect_server:
        survivors = ("-p", f"survivors_file:={config.survivors}") if config.survivors else ()
        specs.append(ChildSpec("detect", "sar_framework.servers.detect_survivor_server", (
            *sim_time, *survivors, *params(config.detect_params))))
    if config.report_server:
        specs.append(ChildSpec("report", "sar_framework.servers.report_survivor_server", (
            *sim_time, "-p", f"report_file:={report_dir / 'reports.jsonl'}",
            *params(config.report_params))))
    plugin_path = (("-p", f"plugin_path:={os.pathsep.join(config.plugin_paths)}")
                   if config.plugin_paths else ())
    specs.append(ChildSpec("runner", "sar_framework.ros.runner", (
        "--params-file", config.params,
        "-p", f"tree:={config.tree}", *sim_time,
        "-p", f"exit_on_completion:={'false' if config.keep_alive else 'true'}",
        "-p", f"status_file:={report_dir / 'status.json'}",
        *plugin_path, *params(config.runner_params))))
    return specs


# -- child processes ----------------------------------------------------------------------
def _parent_death_signal() -> Callable[[], None] | None:
    """A ``preexec_fn`` asking Linux to SIGTERM the child when this process dies."""
    if not sys.platform.startswith("linux"):
        return None
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
    except OSError:
        return None
    prctl = libc.prctl
    pr_set_pdeathsig = 1

    def preexec() -> None:
        prctl(pr_set_pdeathsig, int(signal.SIGTERM))

    return preexec


@dataclass
class LogLine:
    """One line a child printed.

    Attributes:
        child: The child's label.
        severity: ``INFO``, ``WARN``... or ``""`` for a line that is not a ROS log line.
        node: The ROS node's logger name (``""`` when not a ROS log line).
        message: The message (or the whole line).
        wall_s: Wall seconds since the mission started.
    """

    child: str
    severity: str
    node: str
    message: str
    wall_s: float


class Child:
    """A running child process whose output goes to a log file and to a line callback.

    Args:
        spec: What to run.
        env: Its environment.
        log_path: The log file (truncated).
        on_line: Called (from a reader thread) with every line.
        started: ``time.monotonic()`` of the mission start.
    """

    def __init__(self, spec: ChildSpec, env: dict[str, str], log_path: Path,
                 on_line: Callable[[LogLine], None], started: float) -> None:
        self.spec = spec
        self.log_path = log_path
        self._on_line = on_line
        self._started = started
        self._log: IO[str] = log_path.open("w", encoding="utf-8")
        self.proc = subprocess.Popen(
            [sys.executable, "-m", spec.module, "--ros-args", *spec.ros_args],
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
            env=env, start_new_session=True,
            # Safe here: Mission.start forks every child before any reader thread starts.
            preexec_fn=_parent_death_signal(),  # noqa: PLW1509
        )
        self._reader = threading.Thread(target=self._read, name=f"read-{spec.label}",
                                        daemon=True)

    @property
    def label(self) -> str:
        """The child's label."""
        return self.spec.label

    def start_reading(self) -> None:
        """Start the thread that copies the output to the log and the callback."""
        self._reader.start()

    def _read(self) -> None:
        assert self.proc.stdout is not None
        severity, node = "", ""
        for raw in iter(self.proc.stdout.readline, b""):
            text = raw.decode("utf-8", "replace").rstrip("\n")
            self._log.write(text + "\n")
            self._log.flush()
            match = _ROS_LINE.match(text)
            if match:
                severity, node, message = match.groups()
            else:
                message = text  # continuation of a multi-line message keeps its severity
            self._on_line(LogLine(self.label, severity, node, message,
                                  time.monotonic() - self._started))
        self._log.close()

    def poll(self) -> int | None:
        """The exit code, or None while it runs."""
        return self.proc.poll()

    def signal(self, sig: int) -> None:
        """Send ``sig`` to the child's process group (if it still runs)."""
        if self.proc.poll() is None:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(self.proc.pid, sig)

    def finish(self, timeout: float = 1.0) -> None:
        """Wait for the reader thread to drain the output."""
        self._reader.join(timeout=timeout)


def stop_children(children: Sequence[Child], *, first: str = "runner", last: str = "sim",
                  released: threading.Event | None = None) -> float:
    """Stop children in order, SIGKILL after bounds; return the wall seconds it took.

    ``first`` (the runner) and every other child but ``last`` get SIGINT at once; ``last``
    (the simulator, which must still serve while the runner cancels its goal) gets it when
    ``first`` has exited or ``released`` is set (the cancel went through), whichever comes
    first, at the latest after :data:`RUNNER_STOP_S`.

    Args:
        children: The children (some may have exited already).
        first: The label of the child whose exit releases ``last``.
        last: The label of the child stopped last.
        released: Set once ``last`` may stop early (e.g. the goal cancel was seen).
    """
    start = time.monotonic()
    early = [c for c in children if c.label != last]
    late = [c for c in children if c.label == last]
    leader = [c for c in children if c.label == first]
    for child in early:
        child.signal(signal.SIGINT)
    deadline = start + RUNNER_STOP_S
    while (time.monotonic() < deadline and any(c.poll() is None for c in leader)
           and not (released is not None and released.is_set())):
        time.sleep(0.01)
    for child in late:
        child.signal(signal.SIGINT)
    deadline = max(deadline, time.monotonic() + OTHERS_STOP_S)
    while time.monotonic() < deadline and any(c.poll() is None for c in children):
        time.sleep(0.01)
    for child in children:
        if child.poll() is None:
            child.signal(signal.SIGKILL)
    for child in children:
        with contextlib.suppress(subprocess.TimeoutExpired):
            child.proc.wait(timeout=1.0)
    for child in children:
        child.finish(timeout=0.5)
    return time.monotonic() - start


# -- the mission ----------------------------------------------------------------------------
class _Interrupt:
    """SIGINT/SIGTERM set an event the main loop polls."""

    def __init__(self) -> None:
        self.event = threading.Event()
        self.name = ""
        self._previous: dict[int, Any] = {}

    def install(self) -> None:
        for sig in (signal.SIGINT, signal.SIGTERM):
            self._previous[sig] = signal.signal(sig, self._handle)

    def restore(self) -> None:
        for sig, handler in self._previous.items():
            signal.signal(sig, handler)

    def _handle(self, signum: int, _frame: FrameType | None) -> None:
        self.name = signal.Signals(signum).name
        self.event.set()


@dataclass
class Outcome:
    """How a mission ended.

    Attributes:
        status: ``SUCCESS``, ``FAILURE``, ``TIMEOUT``, ``INTERRUPTED`` or ``ERROR``.
        exit_code: The process exit code.
        reason: One line for the user (which node failed and why), or "".
    """

    status: str
    exit_code: int
    reason: str = ""


class Mission:
    """One ``sar-tree run``: children, progress, stop, report.

    Args:
        config: The checked configuration.
        spec: The tree's spec (for the report's tree diagram).
        out: Where progress goes (stdout by default).
    """

    def __init__(self, config: RunConfig, spec: Any, out: IO[str] | None = None) -> None:
        self.config = config
        self.spec = spec
        self.out = out if out is not None else sys.stdout
        self.report_dir = Path(config.report_dir)
        self.children: list[Child] = []
        self.started = time.monotonic()
        self.verdict_line: str | None = None  # "Mission complete." / "Mission failed (...)"
        self.stop_s: float | None = None
        self._print_lock = threading.Lock()
        self._child_errors: dict[str, list[str]] = {}
        self._stopping = False
        self._goal_released = threading.Event()  # the sim answered the cancel of a stop

    # progress -----------------------------------------------------------------------------
    def say(self, text: str) -> None:
        """Print one line of the orchestrator's own."""
        with self._print_lock:
            self.out.write(text + "\n")
            self.out.flush()

    def _on_line(self, line: LogLine) -> None:
        if self._stopping and line.child == "sim" and _GOAL_ENDED.match(line.message):
            self._goal_released.set()
        if line.severity in ("WARN", "ERROR", "FATAL"):
            self._child_errors.setdefault(line.child, []).append(line.message)
        if line.child == "runner" and line.message.startswith(("Mission complete.",
                                                               "Mission failed")):
            self.verdict_line = self.verdict_line or line.message
        shown = (self.config.verbose or line.severity in ("WARN", "ERROR", "FATAL")
                 or (line.severity == "INFO" and _PROGRESS.match(line.message)))
        if shown:
            tag = "" if line.severity in ("INFO", "") else f"{line.severity}: "
            self.say(f"[{line.wall_s:6.2f}s] {line.child:<6} | {tag}{line.message}")

    # life cycle ---------------------------------------------------------------------------
    def prepare(self) -> None:
        """Create the report folder and remove the previous run's outputs from it."""
        self.report_dir.mkdir(parents=True, exist_ok=True)
        for name in ("status.json", "trace.jsonl", "reports.jsonl", "mission.json",
                     "mission.png", "tree.svg", "sim.log", "detect.log", "report.log",
                     "runner.log"):
            (self.report_dir / name).unlink(missing_ok=True)

    def start(self) -> None:
        """Start every child (the reader threads after all forks)."""
        env = ros_environment(log_dir=self.report_dir / "ros_log")
        self.say(
            f"sar-tree run: {self.config.tree} with {self.config.params}; "
            + (f"embedded simulator at {self.config.speed:g}x real time"
               if self.config.sim else "real Nav2 (no simulator)")
            + f"; ROS_DOMAIN_ID={env['ROS_DOMAIN_ID']}; logs in {self.report_dir}/"
        )
        for spec in child_specs(self.config, self.report_dir):
            self.children.append(Child(spec, env, self.report_dir / f"{spec.label}.log",
                                       self._on_line, self.started))
        for child in self.children:
            child.start_reading()
        # Import the report's libraries now, not after a Ctrl-C (numpy, Pillow, graphviz).
        import sar_framework.engine.render
        import sar_framework.report
        import sar_framework.sim.occupancy  # noqa: F401

    def child(self, label: str) -> Child | None:
        """The child called ``label``, if it was started."""
        return next((c for c in self.children if c.label == label), None)

    def wait(self, interrupt: threading.Event) -> Outcome:
        """Wait until the mission ends, a child fails, the timeout passes or Ctrl-C.

        Args:
            interrupt: Set by the signal handler.

        Returns:
            How it ended (children may still run; see :meth:`stop`).
        """
        runner = self.child("runner")
        assert runner is not None
        deadline = self.started + self.config.timeout_s
        announced = False
        while True:
            if interrupt.is_set():
                if self.config.keep_alive and self.verdict_line is not None:
                    return self._verdict_outcome()
                return Outcome("INTERRUPTED", EXIT_INTERRUPTED, "interrupted (Ctrl-C)")
            code = runner.poll()
            if code is not None:
                runner.finish()
                return self._runner_exit_outcome(code)
            for child in self.children:
                if child is not runner and child.poll() is not None:
                    child.finish()
                    return self._child_exit_outcome(child)
            if self.verdict_line is not None and self.config.keep_alive and not announced:
                announced = True
                self.write_report(self._verdict_outcome())
                self.say("Staying up (--keep-alive): static TF and services remain; "
                         "Ctrl-C to exit.")
            if time.monotonic() > deadline and self.verdict_line is None:
                return self._timeout_outcome()
            time.sleep(POLL_S)

    def stop(self) -> None:
        """Stop every child (the simulator after the runner's cancel) and time it."""
        self._stopping = True
        self.stop_s = stop_children(self.children, released=self._goal_released)

    # outcomes -----------------------------------------------------------------------------
    def status_document(self) -> dict[str, Any]:
        """The runner's status file, or ``{}`` when it is missing or unreadable."""
        try:
            return json.loads((self.report_dir / "status.json").read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return {}

    def _failure_reason(self) -> str:
        status = self.status_document()
        failures = status.get("failures") or []
        if failures:
            last = failures[-1]
            return (f"{last.get('name')} [{last.get('uid')}] failed: "
                    f"{last.get('message') or 'no reason given'}")
        if status.get("error"):
            return str(status.get("error"))
        return self.verdict_line or "no reason given"

    def _verdict_outcome(self) -> Outcome:
        if self.verdict_line and self.verdict_line.startswith("Mission complete."):
            return Outcome("SUCCESS", EXIT_OK)
        return Outcome("FAILURE", EXIT_FAILURE, self._failure_reason())

    def _runner_exit_outcome(self, code: int) -> Outcome:
        if code == 0:
            return Outcome("SUCCESS", EXIT_OK)
        if code == 1:
            return Outcome("FAILURE", EXIT_FAILURE, self._failure_reason())
        last = self._last_error("runner")
        if code == 2:
            return Outcome("ERROR", EXIT_USAGE, f"the runner rejected its input: {last}")
        return Outcome("ERROR", EXIT_FAILURE, f"the runner exited ({code}): {last}")

    def _child_exit_outcome(self, child: Child) -> Outcome:
        code = child.poll()
        last = self._last_error(child.label)
        exit_code = EXIT_USAGE if code == 2 else EXIT_FAILURE
        return Outcome("ERROR", exit_code,
                       f"the {child.label} process exited ({code}) mid-mission: {last}")

    def _timeout_outcome(self) -> Outcome:
        status = self.status_document()
        running = list(status.get("running") or [])
        names = {n.uid: n.name for n in self.spec.nodes()} if self.spec is not None else {}
        leaves = [u for u in running if not any(o != u and o.startswith(u + ".")
                                                for o in running)]
        where = ", ".join(f"{names.get(u, u)} [{u}]" for u in leaves) or "no node RUNNING"
        failures = status.get("failures") or []
        last = (f"; last failure: {failures[-1].get('name')} [{failures[-1].get('uid')}]: "
                f"{failures[-1].get('message')}") if failures else ""
        return Outcome("TIMEOUT", EXIT_FAILURE,
                       f"timeout after {self.config.timeout_s:g} s; still running: {where}{last}")

    def _last_error(self, label: str) -> str:
        errors = self._child_errors.get(label)
        if errors:
            return errors[-1]
        child = self.child(label)
        if child is not None and child.log_path.exists():
            lines = child.log_path.read_text(errors="replace").strip().splitlines()
            if lines:
                return lines[-1]
        return "no output"

    # report -------------------------------------------------------------------------------
    def write_report(self, outcome: Outcome) -> list[Path]:
        """Write mission.json, mission.png and tree.svg; return the files written.

        Args:
            outcome: How the mission ended.
        """
        from sar_framework.report import MissionInputs, write_report

        inputs = MissionInputs(
            report_dir=self.report_dir, tree=self.config.tree, params_file=self.config.params,
            spec=self.spec, outcome=outcome.status, reason=outcome.reason,
            wall_duration_s=time.monotonic() - self.started,
        )
        try:
            return write_report(inputs)
        except Exception as err:  # a report problem must not hide the mission's verdict
            self.say(f"sar-tree run: warning: could not write the report: "
                     f"{type(err).__name__}: {err}")
            return []


def run_mission(config: RunConfig, spec: Any, out: IO[str] | None = None) -> int:
    """Run a checked mission; return the exit code.

    Args:
        config: The configuration (already checked by :func:`check_config`).
        spec: The tree's spec.
        out: Where progress goes (stdout by default).

    Returns:
        0 SUCCESS, 1 FAILURE/timeout/start-up failure, 2 input rejected by a child,
        130 interrupted.
    """
    mission = Mission(config, spec, out)
    interrupt = _Interrupt()
    interrupt.install()
    try:
        mission.prepare()
        mission.start()
        outcome = mission.wait(interrupt.event)
        if outcome.status == "TIMEOUT":
            mission.say(f"sar-tree run: {outcome.reason}; stopping")
        if outcome.status == "INTERRUPTED":
            mission.say(f"sar-tree run: {interrupt.name or 'interrupted'}: stopping "
                        "(the goal in flight is cancelled)")
    finally:
        mission.stop()
        interrupt.restore()
    written = mission.write_report(outcome)
    _summarise(mission, outcome, written)
    return outcome.exit_code


def _summarise(mission: Mission, outcome: Outcome, written: Sequence[Path]) -> None:
    """Print the final lines: verdict, numbers, failures, where the report is."""
    summary: dict[str, Any] = {}
    mission_json = mission.report_dir / "mission.json"
    if mission_json in written:
        summary = json.loads(mission_json.read_text(encoding="utf-8"))
    zones = list(dict.fromkeys(z["id"] for z in summary.get("zones_visited", [])))
    survivors = [s["id"] for s in summary.get("survivors", []) if s.get("acknowledged")]
    parts = [f"Mission {outcome.status}"]
    if summary:
        parts.append(f"{summary.get('wall_duration_s', 0):.1f} s wall, "
                     f"{summary.get('sim_duration_s') or 0:.1f} s simulated, "
                     f"{summary.get('ticks', 0)} ticks")
        parts.append(f"zones visited: {', '.join(zones) or 'none'}")
        parts.append(f"survivors reported: {', '.join(survivors) or 'none'}")
    mission.say("sar-tree run: " + "; ".join(parts))
    if outcome.reason:
        mission.say(f"sar-tree run: {outcome.reason}")
    if outcome.status == "INTERRUPTED" and mission.stop_s is not None:
        mission.say(f"sar-tree run: every process stopped {mission.stop_s:.2f} s after the "
                    "signal")
    if outcome.status == "SUCCESS":
        # A retried leaf can fail the same way several times: one note each, with a count.
        counts = Counter((f["name"], f["uid"], f["message"]) for f in summary.get("failures", []))
        for (name, uid, message), count in counts.items():
            times = f" ({count} times)" if count > 1 else ""
            mission.say(f"sar-tree run: note: {name} [{uid}] failed on the way{times}: {message}")
    if written:
        mission.say(f"sar-tree run: report in {mission.report_dir}/ "
                    f"({', '.join(p.name for p in written)}; child logs *.log)")


def run_command(args: argparse.Namespace) -> int:
    """``sar-tree run``: check the input, run the mission, return the exit code.

    Args:
        args: Parsed arguments (see :func:`configure`).

    Returns:
        The exit code.
    """
    config = config_from_args(args)
    try:
        spec = check_config(config)
    except RunUsageError as err:
        sys.stderr.write(f"sar-tree run: error: {err}\n" if "\n" not in str(err)
                         else f"{err}\nsar-tree run: error: invalid tree\n")
        return EXIT_USAGE
    return run_mission(config, spec)
