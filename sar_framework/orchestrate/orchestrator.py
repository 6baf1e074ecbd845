"""One ``sar-tree run``: start the children, follow the mission, stop, report, summarise.

The mission is followed through the runner's events (``events.jsonl``, read as it grows):
progress lines, the verdict and the stop come from them; child logs are copied to files
and their warnings shown, for humans only.
"""

from __future__ import annotations

import signal
import sys
import threading
import time
from pathlib import Path
from typing import IO

from sar_framework.child_process import ChildProcess
from sar_framework.events.event import EventKind, MissionEvent
from sar_framework.events.jsonl import (
    EVENTS_FILE,
    EventFileFollower,
    EventFileWriter,
    JsonLinesFollower,
)
from sar_framework.mission.completion import DEFAULT_COMPLETION, describe_completion
from sar_framework.orchestrate.config import ChildSpec, child_specs, ros_environment
from sar_framework.orchestrate.inputs import CheckedInputs
from sar_framework.orchestrate.options import RunConfig
from sar_framework.orchestrate.outcome import (
    EXIT_INTERRUPTED,
    EXIT_USAGE,
    Outcome,
    child_exit_outcome,
    completion_outcome,
    exit_words,
    exited_children,
    progress_line,
    read_status,
    runner_exit_outcome,
    summarise,
    timeout_outcome,
)
from sar_framework.orchestrate.repeats import RepeatCollapser, numbers_as_one
from sar_framework.orchestrate.supervise import LogLine, start_child, stop_children
from sar_framework.run_clock import RUN_STARTED_ENV, process_started
from sar_framework.stop_signals import stop_on_signals
from sar_framework.watch.child import start_watcher, stop_watcher

POLL_S = 0.05
GOAL_ENDS = frozenset({"canceled", "aborted", "succeeded"})
"""The simulator's trace events that end a goal (a stop may release the simulator then)."""


class Orchestrator:
    """One ``sar-tree run``: children, progress, stop, report.

    Args:
        config: The checked configuration.
        inputs: What the checks found (the tree's spec, the runner's parameters, the apps' places).
        out: Where progress goes (stdout by default).
    """

    def __init__(self, config: RunConfig, inputs: CheckedInputs,
                 out: IO[str] | None = None) -> None:
        self.config = config
        self.inputs = inputs
        self.spec = inputs.spec
        self.out = out if out is not None else sys.stdout
        self.report_dir = Path(config.report_dir)
        self.children: list[ChildProcess] = []
        self.started = process_started()  # every wall_s of the run counts from here
        self.events: list[MissionEvent] = []
        self.completion: MissionEvent | None = None  # the runner's verdict
        self.completion_wall_s: float | None = None  # when it came (--keep-alive's figures)
        self._repeats = RepeatCollapser()  # a line repeating a recent one is counted
        self._follower = EventFileFollower(self.report_dir / EVENTS_FILE)
        self._trace = JsonLinesFollower(self.report_dir / "trace.jsonl")
        self.stop_s: float | None = None
        self._print_lock = threading.Lock()
        self._child_errors: dict[str, list[str]] = {}
        self.exited: dict[str, int | None] = {}  # children that ended mid-mission
        self.watcher: ChildProcess | None = None  # sar-tree run --watch
        self._report_imported = False
        self._in_flight = 0  # goals in flight, once the trace is followed (at completion)
        self._stopped_early = False  # the children but the runner signalled at completion

    # progress -----------------------------------------------------------------------------
    def say(self, text: str) -> None:
        """Print one line of the orchestrator's own."""
        with self._print_lock:
            self.out.write(text + "\n")
            self.out.flush()

    def _on_line(self, line: LogLine) -> None:
        """A child's log line: kept for error messages, shown when a warning (or -v)."""
        if line.severity in ("WARN", "ERROR", "FATAL"):
            self._child_errors.setdefault(line.child, []).append(line.message)
        shown = self.config.verbose or line.severity in ("WARN", "ERROR", "FATAL")
        if shown and self.watcher is None:
            tag = "" if line.severity in ("INFO", "") else f"{line.severity}: "
            self.show(line.wall_s, line.child, f"{tag}{line.message}", log_line=True)

    def show(self, wall_s: float, child: str, text: str, *, log_line: bool = False) -> None:
        """Print a child's line unless it repeats a recent one (then it is counted).

        A process's log line counts as a repeat whatever its numbers (goal counters,
        timings); an event's line only when it is the same text.
        """
        line = f"{child:<6} | {text}"
        with self._print_lock:
            shown = self._repeats.lines(line, numbers_as_one(line) if log_line else None)
        for line in shown:
            self.say(f"[{wall_s:6.2f}s] {line}")

    def take_events(self) -> None:
        """Read the runner's new events: note its verdict, show the progress ones."""
        for event in self._follower.poll():
            self.events.append(event)
            if event.kind == EventKind.COMPLETION and self.completion is None:
                self.completion = event
                self.completion_wall_s = time.monotonic() - self.started
            line = progress_line(event, self.inputs.apps)
            if line is not None and self.watcher is None:
                self.show(time.monotonic() - self.started, "runner", line)
        if self.events:
            self.import_report_libraries()

    def flush_repeats(self) -> None:
        """Print the count of the lines held back, if any."""
        with self._print_lock:
            held = self._repeats.flush()
        for line in held:
            self.say(f"[{time.monotonic() - self.started:6.2f}s] {line}")

    def _goals_in_flight(self) -> int:
        """Goals the simulator's trace shows accepted and not yet ended (read on from here)."""
        for record in self._trace.poll():
            if isinstance(record, dict) and record.get("event") == "accepted":
                self._in_flight += 1
            elif isinstance(record, dict) and record.get("event") in GOAL_ENDS:
                self._in_flight = max(0, self._in_flight - 1)
        return self._in_flight

    def stop_early_after_completion(self) -> None:
        """The mission is complete and the runner ends by itself: stop the others meanwhile.

        Every child but the runner and the recorder (which records the runner's last
        events) gets SIGINT now, not after the runner's exit, unless a goal is still in
        flight (the simulator must then answer the runner's cancel). :meth:`stop` still
        waits for all of them, and for the runner's exit code.
        """
        if self._stopped_early or self._goals_in_flight() > 0:
            return
        self._stopped_early = True
        for child in self.children:
            if child.label not in ("runner", "recorder") and child.poll() is None:
                child.signal(signal.SIGINT)

    def _goal_ended(self) -> bool:
        """Whether the simulator's trace says a goal ended since the last call."""
        return any(isinstance(r, dict) and r.get("event") in GOAL_ENDS
                   for r in self._trace.poll())

    # life cycle ---------------------------------------------------------------------------
    def prepare(self) -> None:
        """Create the report folder and remove the previous run's outputs from it."""
        self.report_dir.mkdir(parents=True, exist_ok=True)
        apps = self.inputs.apps
        for name in ("status.json", EVENTS_FILE, "trace.jsonl", "mission.json", "mission.png",
                     "tree.svg", "sim.log", "runner.log",
                     *(name for app in apps for name in app.run_files),
                     *(f"{kind.label}.log" for app in apps for kind in app.process_kinds)):
            (self.report_dir / name).unlink(missing_ok=True)
        if self.config.record:
            Path(self.config.record).unlink(missing_ok=True)

    def start(self) -> None:
        """Start every child (the reader threads after all forks)."""
        env = ros_environment(log_dir=self.report_dir / "ros_log")
        env[RUN_STARTED_ENV] = repr(self.started)  # the runner's events count from it too
        self.say(
            f"sar-tree run: {self.config.tree}"
            + (f" with {self.config.params}; " if self.config.params else "; ")
            + (f"embedded simulator at {self.config.speed:g}x real time"
               if self.config.sim else "real Nav2 (no simulator)")
            + f"; ROS_DOMAIN_ID={env['ROS_DOMAIN_ID']}; logs in {self.report_dir}/"
        )
        self.say("sar-tree run: " + describe_completion(
            str(self.inputs.runner_values.get("completion", DEFAULT_COMPLETION)), self.spec))
        for spec in self.child_specs():
            self.children.append(start_child(spec, env, self.report_dir / f"{spec.label}.log",
                                             self._on_line, self.started))
            if spec.label == "recorder" and self.config.record:
                from sar_framework.recording.recorder import wait_until_recording  # mcap: slow

                recorder = self.children[-1]
                wait_until_recording(Path(self.config.record),
                                     lambda child=recorder: child.poll() is None)
        for child in self.children:
            child.start_reading()
        if self.config.watch:
            self.watcher = start_watcher(env)

    def import_report_libraries(self) -> None:
        """Import what the report needs (numpy, Pillow, graphviz) at the runner's first event.

        Not at start-up, where it would take a core from the children starting; before the
        mission is under way, so a Ctrl-C mid-mission is not slowed by it.
        """
        if self._report_imported:
            return
        self._report_imported = True
        import sar_framework.engine.rendering.render
        import sar_framework.report
        import sar_framework.sim.occupancy  # noqa: F401

    def child_specs(self) -> list[ChildSpec]:
        """The processes to start, in order."""
        return child_specs(self.config, self.report_dir, self.inputs.places,
                           apps=self.inputs.apps)

    def child(self, label: str) -> ChildProcess | None:
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
            self.take_events()
            if interrupt.is_set():
                if self.config.keep_alive and self.completion is not None:
                    return completion_outcome(self.completion, self.events)
                return Outcome("INTERRUPTED", EXIT_INTERRUPTED, "interrupted (Ctrl-C)")
            code = runner.poll()
            if code is not None:
                runner.finish_reading()
                self.take_events()  # the last events, written before it exited
                return runner_exit_outcome(code, self.events, read_status(self.report_dir),
                                           self.last_error("runner"), spec=self.spec,
                                           sim_timeout_s=self.config.sim_timeout_s)
            for child in self.children:
                if (child is runner or child.label in self.exited or child.poll() is None
                        or self._stopped_early):  # then they end because we asked
                    continue
                child.finish_reading()
                self.exited[child.label] = child.poll()
                if child.label == "sim" or child.poll() == EXIT_USAGE:  # the clock, bad input
                    return child_exit_outcome(child.label, child.poll(),
                                              self.last_error(child.label))
                self.say(f"sar-tree run: the {child.label} process {exit_words(child.poll())} "
                         "mid-mission; the tree goes on without its service")
            if self.completion is not None and not self.config.keep_alive:
                self.stop_early_after_completion()
            if self.completion is not None and self.config.keep_alive and not announced:
                announced = True
                self.write_report(completion_outcome(self.completion, self.events))
                self.say("Staying up (--keep-alive): static TF and services remain; "
                         "Ctrl-C to exit.")
            if time.monotonic() > deadline and self.completion is None:
                return timeout_outcome(self.config.timeout_s, read_status(self.report_dir),
                                       self.spec, self.events)
            time.sleep(POLL_S)

    def stop(self) -> None:
        """Stop every child (the simulator after the runner's cancel) and time it."""
        self._trace.poll()  # what the trace said before the stop does not release it
        self.stop_s = stop_children(self.children, released=self._goal_ended)
        self.take_events()
        self.flush_repeats()
        if self.watcher is not None:
            stop_watcher(self.watcher)

    def last_error(self, label: str) -> str:
        """Child ``label``'s last warning or error line (else its log's last line)."""
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
    def record_verdict(self, outcome: Outcome) -> None:
        """Close the event stream with the run's ``verdict`` (after every child stopped).

        Args:
            outcome: How the mission ended.
        """
        self.append_verdict(self.events, self.report_dir, outcome)

    def append_verdict(self, events: list[MissionEvent], folder: Path, outcome: Outcome,
                       who: str = "") -> None:
        """Append a ``verdict`` event after ``events`` to ``folder``'s events file and list.

        Args:
            events: The stream so far (the verdict is appended to it once written).
            folder: Where its events file is.
            outcome: The verdict's status and reason.
            who: Whose stream, for the warning when the file cannot be written.
        """
        last = events[-1] if events else None
        verdict = MissionEvent(
            kind=EventKind.VERDICT, seq=(last.seq if last else 0) + 1,
            sim_s=last.sim_s if last else 0.0,
            wall_s=round(time.monotonic() - self.started, 3), status=outcome.status,
            message=outcome.reason or f"Mission {outcome.status}")
        try:
            writer = EventFileWriter(folder / EVENTS_FILE, append=True)
        except OSError as err:
            whose = f"{who}: " if who else ""
            self.say(f"sar-tree run: warning: {whose}could not write the verdict event: {err}")
            return
        writer(verdict)
        writer.close()
        events.append(verdict)

    def conclude(self, outcome: Outcome, written: list[Path]) -> int:
        """Print the final lines; return the exit code.

        Args:
            outcome: How the mission ended.
            written: The report files written.
        """
        summarise(self.say, self.report_dir, outcome, written, self.stop_s,
                  recording=Path(self.config.record) if self.config.record else None,
                  apps=self.inputs.apps)
        return outcome.exit_code

    def write_report(self, outcome: Outcome) -> list[Path]:
        """Write mission.json, mission.png and tree.svg; return the files written.

        Args:
            outcome: How the mission ended.
        """
        from sar_framework.report import MissionInputs, write_report

        inputs = MissionInputs(
            report_dir=self.report_dir, tree=self.config.tree, params_file=self.config.params,
            spec=self.spec, outcome=outcome.status, reason=outcome.reason,
            wall_duration_s=(self.completion_wall_s
                             if self.config.keep_alive and self.completion_wall_s is not None
                             else time.monotonic() - self.started),
            blocked_areas=self.inputs.blocked_areas, apps=self.inputs.apps,
        )
        try:
            return write_report(inputs)
        except Exception as err:  # a report problem must not hide the mission's verdict
            self.say(f"sar-tree run: warning: could not write the report: "
                     f"{type(err).__name__}: {err}")
            return []


def run_mission(mission: Orchestrator) -> int:
    """Run a checked mission; return the exit code.

    Args:
        mission: The mission (an :class:`Orchestrator` of checked inputs, or a fleet's).

    Returns:
        0 SUCCESS, 1 FAILURE/timeout/start-up failure, 2 input rejected by a child,
        130 interrupted.
    """
    interrupt = stop_on_signals()
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
        outcome.reason = "; ".join([outcome.reason, *exited_children(mission.exited)]).strip("; ")
    mission.record_verdict(outcome)
    written = mission.write_report(outcome)
    return mission.conclude(outcome, written)
