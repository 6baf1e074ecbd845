"""One ``sar-tree run``: start the children, follow the mission, stop, report, summarise."""

from __future__ import annotations

import argparse
import sys
import threading
import time
from pathlib import Path
from typing import IO

from sar_framework.mission.completion import DEFAULT_COMPLETION, describe_completion
from sar_framework.recording.recorder import wait_until_recording
from sar_framework.run.config import (
    RunConfig,
    RunUsageError,
    check_config,
    child_specs,
    config_from_args,
    ros_environment,
)
from sar_framework.run.inputs import CheckedInputs
from sar_framework.run.outcome import (
    EXIT_INTERRUPTED,
    EXIT_USAGE,
    VERDICT_PREFIXES,
    Outcome,
    child_exit_outcome,
    exit_words,
    is_progress,
    read_status,
    runner_exit_outcome,
    summarise,
    timeout_outcome,
    verdict_outcome,
)
from sar_framework.run.supervise import GOAL_ENDED, Child, Interrupt, LogLine, stop_children
from sar_framework.watch.child import WatchChild

POLL_S = 0.05


class Mission:
    """One ``sar-tree run``: children, progress, stop, report.

    Args:
        config: The checked configuration.
        inputs: What the checks found (the tree's spec, the runner's parameters, zones).
        out: Where progress goes (stdout by default).
    """

    def __init__(self, config: RunConfig, inputs: CheckedInputs,
                 out: IO[str] | None = None) -> None:
        self.config = config
        self.inputs = inputs
        self.spec = inputs.spec
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
        self.exited: dict[str, int | None] = {}  # children that ended mid-mission
        self.watcher: WatchChild | None = None  # sar-tree run --watch

    # progress -----------------------------------------------------------------------------
    def say(self, text: str) -> None:
        """Print one line of the orchestrator's own."""
        with self._print_lock:
            self.out.write(text + "\n")
            self.out.flush()

    def _on_line(self, line: LogLine) -> None:
        if self._stopping and line.child == "sim" and GOAL_ENDED.match(line.message):
            self._goal_released.set()
        if line.severity in ("WARN", "ERROR", "FATAL"):
            self._child_errors.setdefault(line.child, []).append(line.message)
        if line.child == "runner" and line.message.startswith(VERDICT_PREFIXES):
            self.verdict_line = self.verdict_line or line.message
        shown = (self.config.verbose or line.severity in ("WARN", "ERROR", "FATAL")
                 or (line.severity == "INFO" and is_progress(line.message)))
        if shown and self.watcher is None:
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
        if self.config.record:
            Path(self.config.record).unlink(missing_ok=True)

    def start(self) -> None:
        """Start every child (the reader threads after all forks)."""
        env = ros_environment(log_dir=self.report_dir / "ros_log")
        self.say(
            f"sar-tree run: {self.config.tree} with {self.config.params}; "
            + (f"embedded simulator at {self.config.speed:g}x real time"
               if self.config.sim else "real Nav2 (no simulator)")
            + f"; ROS_DOMAIN_ID={env['ROS_DOMAIN_ID']}; logs in {self.report_dir}/"
        )
        self.say("sar-tree run: " + describe_completion(
            str(self.inputs.runner_values.get("completion", DEFAULT_COMPLETION)), self.spec))
        for spec in child_specs(self.config, self.report_dir, self.inputs.zones):
            self.children.append(Child(spec, env, self.report_dir / f"{spec.label}.log",
                                       self._on_line, self.started))
            if spec.label == "recorder" and self.config.record:
                recorder = self.children[-1]
                wait_until_recording(Path(self.config.record),
                                     lambda child=recorder: child.poll() is None)
        for child in self.children:
            child.start_reading()
        if self.config.watch:
            self.watcher = WatchChild(env)
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
                    return verdict_outcome(self.verdict_line, read_status(self.report_dir))
                return Outcome("INTERRUPTED", EXIT_INTERRUPTED, "interrupted (Ctrl-C)")
            code = runner.poll()
            if code is not None:
                runner.finish()
                return runner_exit_outcome(code, read_status(self.report_dir),
                                           self.verdict_line, self._last_error("runner"))
            for child in self.children:
                if child is runner or child.label in self.exited or child.poll() is None:
                    continue
                child.finish()
                self.exited[child.label] = child.poll()
                if child.label == "sim" or child.poll() == EXIT_USAGE:  # the clock, bad input
                    return child_exit_outcome(child.label, child.poll(),
                                              self._last_error(child.label))
                self.say(f"sar-tree run: the {child.label} process {exit_words(child.poll())} "
                         "mid-mission; the tree goes on without its service")
            if self.verdict_line is not None and self.config.keep_alive and not announced:
                announced = True
                self.write_report(verdict_outcome(self.verdict_line,
                                                  read_status(self.report_dir)))
                self.say("Staying up (--keep-alive): static TF and services remain; "
                         "Ctrl-C to exit.")
            if time.monotonic() > deadline and self.verdict_line is None:
                return timeout_outcome(self.config.timeout_s, read_status(self.report_dir),
                                       self.spec)
            time.sleep(POLL_S)

    def stop(self) -> None:
        """Stop every child (the simulator after the runner's cancel) and time it."""
        self._stopping = True
        self.stop_s = stop_children(self.children, released=self._goal_released)
        if self.watcher is not None:
            self.watcher.finish()

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
            blocked_areas=self.inputs.blocked_areas,
        )
        try:
            return write_report(inputs)
        except Exception as err:  # a report problem must not hide the mission's verdict
            self.say(f"sar-tree run: warning: could not write the report: "
                     f"{type(err).__name__}: {err}")
            return []


def run_mission(config: RunConfig, inputs: CheckedInputs, out: IO[str] | None = None) -> int:
    """Run a checked mission; return the exit code.

    Args:
        config: The configuration (already checked by :func:`check_config`).
        inputs: What :func:`check_config` found.
        out: Where progress goes (stdout by default).

    Returns:
        0 SUCCESS, 1 FAILURE/timeout/start-up failure, 2 input rejected by a child,
        130 interrupted.
    """
    mission = Mission(config, inputs, out)
    interrupt = Interrupt()
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
    if mission.exited and outcome.status != "SUCCESS":
        outcome.reason = "; ".join([outcome.reason, *(
            f"the {label} process had {exit_words(code)}" for label, code in mission.exited.items()
            if label != "sim")]).strip("; ")
    written = mission.write_report(outcome)
    summarise(mission.say, mission.report_dir, outcome, written, mission.stop_s)
    return outcome.exit_code


def run_command(args: argparse.Namespace) -> int:
    """``sar-tree run``: check the input, run the mission, return the exit code.

    Args:
        args: Parsed arguments (see :func:`~sar_framework.run.config.configure`).

    Returns:
        The exit code.
    """
    config = config_from_args(args)
    try:
        inputs = check_config(config)
    except RunUsageError as err:
        lines = str(err).splitlines()
        if len(lines) == 1:
            sys.stderr.write(f"sar-tree run: error: {lines[0]}\n")
        else:
            sys.stderr.write("\n".join(lines) + f"\nsar-tree run: error: {len(lines)} "
                             "problems in the inputs; nothing was started\n")
        return EXIT_USAGE
    return run_mission(config, inputs)
