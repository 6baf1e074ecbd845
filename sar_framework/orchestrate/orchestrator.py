"""One ``sar-tree run``: start the children, follow the mission, stop, report, summarise.

The mission is followed through each runner's events (``events.jsonl``, read as it grows):
progress lines, the verdict and the stop come from them; child logs are copied to files
and their warnings shown, for humans only. One robot or several, one path: each robot has
its runner, its events, its verdict and its report (the unnamed robot of a run that names
none in the report folder, a named one in ``RUN/<name>/``); named robots' run ends once
every runner has ended, with the run's page (:mod:`.run_report`).
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
from sar_framework.events.jsonl import EVENTS_FILE, EventFileFollower
from sar_framework.mission.completion import DEFAULT_COMPLETION, describe_completion
from sar_framework.mission.processes import Robot
from sar_framework.orchestrate.config import ChildSpec, child_specs, ros_environment
from sar_framework.orchestrate.inputs import CheckedInputs
from sar_framework.orchestrate.options import RunConfig
from sar_framework.orchestrate.outcome import (
    EXIT_FAILURE,
    EXIT_INTERRUPTED,
    EXIT_USAGE,
    Outcome,
    child_exit_outcome,
    completion_outcome,
    exit_words,
    progress_line,
    read_status,
    runner_exit_outcome,
    summarise,
    timeout_outcome,
)
from sar_framework.orchestrate.repeats import RepeatCollapser, numbers_as_one
from sar_framework.orchestrate.robots import write_fleet_file
from sar_framework.orchestrate.run_report import (
    ROBOT_FILES,
    RUN_FILES,
    append_verdict,
    conclude_robots,
    import_report_libraries,
    robot_report,
    robots_page,
)
from sar_framework.orchestrate.supervise import GoalTraces, LogLine, start_child, stop_children
from sar_framework.run_clock import RUN_STARTED_ENV, process_started
from sar_framework.watch.child import start_watcher, stop_watcher

POLL_S = 0.05


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
        self.robots: dict[str, Robot] = {robot.name: robot for robot in inputs.robots}
        self.named = any(self.robots)  # --robots/--fleet: each robot in its namespace
        self.robot_events: dict[str, list[MissionEvent]] = {name: [] for name in self.robots}
        self.completions: dict[str, MissionEvent] = {}  # each runner's verdict
        self.completion_wall_s: float | None = None  # when the last came (--keep-alive)
        self.outcomes: dict[str, Outcome] = {}  # each robot's verdict, once its runner ended
        self.verdict: Outcome | None = None  # named robots: the run's, with its report
        self._repeats = RepeatCollapser()  # a line repeating a recent one is counted
        self._followers = {name: EventFileFollower(self.robot_dir(name) / EVENTS_FILE)
                           for name in self.robots}
        self._goals = GoalTraces([self.robot_dir(name) / "trace.jsonl" for name in self.robots])
        self.stop_s: float | None = None
        self._print_lock = threading.Lock()
        self._child_errors: dict[str, list[str]] = {}
        self.exited: dict[str, int | None] = {}  # children that ended mid-mission
        self.watcher: ChildProcess | None = None  # sar-tree run --watch
        self._stopped_early = False  # the children but the runner signalled at completion

    def robot_dir(self, name: str) -> Path:
        """Robot ``name``'s files: the report folder, or ``RUN/<name>`` when it is named."""
        return self.report_dir / name if name else self.report_dir

    @property
    def events(self) -> list[MissionEvent]:
        """Every robot's events so far (the one robot's stream, when it is one)."""
        if not self.named:
            return self.robot_events[""]
        return [event for events in self.robot_events.values() for event in events]

    @property
    def completion(self) -> MissionEvent | None:
        """The runners' verdict once every one announced it (the last), else None."""
        if len(self.completions) < len(self.robots):
            return None
        return list(self.completions.values())[-1]

    def runner_label(self, name: str) -> str:
        """Robot ``name``'s runner's label (``runner``, ``robot1/runner``)."""
        return f"{name}/runner" if name else "runner"

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
        """Read each runner's new events: note its verdict, show the progress ones."""
        for name, follower in self._followers.items():
            for event in follower.poll():
                self.robot_events[name].append(event)
                if event.kind == EventKind.COMPLETION and name not in self.completions:
                    self.completions[name] = event
                    self.completion_wall_s = time.monotonic() - self.started
                line = progress_line(event, self.inputs.apps)
                if line is not None and self.watcher is None:
                    self.show(time.monotonic() - self.started, name or "runner", line)
        if any(self.robot_events.values()):
            import_report_libraries()

    def flush_repeats(self) -> None:
        """Print the count of the lines held back, if any."""
        with self._print_lock:
            held = self._repeats.flush()
        for line in held:
            self.say(f"[{time.monotonic() - self.started:6.2f}s] {line}")

    def stop_early_after_completion(self) -> None:
        """Every mission is complete and the runners end by themselves: stop the others.

        Every child but the runners and the recorder (which records the runners' last
        events) gets SIGINT now, not after the runners' exit, unless a goal is still in
        flight (the simulator must then answer the runner's cancel). :meth:`stop` still
        waits for all of them, and for the runners' exit codes.
        """
        if self._stopped_early or self._goals.in_flight() > 0:
            return
        self._stopped_early = True
        for child in self.children:
            if child.label.rpartition("/")[2] not in ("runner", "recorder") \
                    and child.poll() is None:
                child.signal(signal.SIGINT)

    # life cycle ---------------------------------------------------------------------------
    def prepare(self) -> None:
        """Create the report folders, remove the previous run's outputs, write the fleet file.

        The fleet file is the one ``--robots N`` asks for (named robots only).
        """
        self.report_dir.mkdir(parents=True, exist_ok=True)
        apps = self.inputs.apps
        for name in ("status.json", EVENTS_FILE, "trace.jsonl", "mission.json", "mission.png",
                     "tree.svg", "sim.log", "runner.log", *RUN_FILES,
                     *(name for app in apps for name in app.run_files),
                     *(f"{kind.label}.log" for app in apps for kind in app.process_kinds)):
            (self.report_dir / name).unlink(missing_ok=True)
        for robot in self.robots if self.named else ():
            self.robot_dir(robot).mkdir(exist_ok=True)
            for name in ROBOT_FILES:
                (self.robot_dir(robot) / name).unlink(missing_ok=True)
        if self.config.record:
            Path(self.config.record).unlink(missing_ok=True)
        if self.named:
            fleet = write_fleet_file(self.config, self.report_dir, self.inputs.robots)
            self.say(f"sar-tree run: {len(self.robots)} robots ({', '.join(self.robots)}) "
                     f"from {fleet}")

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

    def child_specs(self) -> list[ChildSpec]:
        """The processes to start, in order."""
        return child_specs(self.config, self.report_dir, self.inputs.places,
                           apps=self.inputs.apps, robots=self.inputs.robots,
                           node_kinds=self.inputs.node_kinds)

    def child(self, label: str) -> ChildProcess | None:
        """The child called ``label``, if it was started."""
        return next((c for c in self.children if c.label == label), None)

    def wait(self, interrupt: threading.Event) -> Outcome:
        """Wait until every runner ended, a child fails, the timeout passes or Ctrl-C.

        Each robot's verdict goes into :attr:`outcomes` as its runner ends.

        Args:
            interrupt: Set by the signal handler.

        Returns:
            How it ended (children may still run; see :meth:`stop`): the one robot's
            verdict; for named robots a placeholder SUCCESS once every runner ended (the
            run's verdict comes with the reports), else how the run was cut short.
        """
        runners = {name: self.child(self.runner_label(name)) for name in self.robots}
        deadline = self.started + self.config.timeout_s
        announced = False
        while True:
            self.take_events()
            left = [name for name in self.robots if name not in self.outcomes]
            if interrupt.is_set():
                if self.config.keep_alive and self.completion is not None:
                    return completion_outcome(self.completion, self.events)
                return self._cut_short(left, Outcome("INTERRUPTED", EXIT_INTERRUPTED,
                                                     "interrupted (Ctrl-C)"))
            for name in left:
                self._runner_ended(name, runners[name])
            if all(name in self.outcomes for name in self.robots):
                return self.outcomes[""] if not self.named else Outcome("SUCCESS", 0)
            left = [name for name in self.robots if name not in self.outcomes]
            for child in self.children:
                if (child.label.rpartition("/")[2] == "runner" or child.label in self.exited
                        or child.poll() is None
                        or self._stopped_early):  # then they end because we asked
                    continue
                child.finish_reading()
                self.exited[child.label] = child.poll()
                if child.label == "sim" or child.poll() == EXIT_USAGE:  # the clock, bad input
                    return self._cut_short(left, child_exit_outcome(
                        child.label, child.poll(), self.last_error(child.label)))
                self.say(f"sar-tree run: the {child.label} process {exit_words(child.poll())} "
                         "mid-mission; the " + ("robots go on" if self.named else
                                                "tree goes on") + " without its service")
            if self.completion is not None and not self.config.keep_alive:
                self.stop_early_after_completion()
            if self.completion is not None and self.config.keep_alive and not announced:
                announced = True
                self.write_report(completion_outcome(self.completion, self.events))
                self.say("Staying up (--keep-alive): static TF and services remain; "
                         "Ctrl-C to exit.")
            if time.monotonic() > deadline and self.completion is None:
                return self._timed_out(left)
            time.sleep(POLL_S)

    def _runner_ended(self, name: str, runner: ChildProcess | None) -> None:
        """Robot ``name``'s verdict, when its runner has ended (or never started)."""
        if runner is None:  # never started: nothing to wait for
            self.outcomes[name] = Outcome("ERROR", EXIT_FAILURE, "no runner started")
            return
        code = runner.poll()
        if code is None:
            return
        runner.finish_reading()
        self.take_events()  # the last events, written before it exited
        self.outcomes[name] = runner_exit_outcome(
            code, self.robot_events[name], read_status(self.robot_dir(name)),
            self.last_error(runner.label), spec=self.spec,
            sim_timeout_s=self.config.sim_timeout_s)
        if self.named:
            own = self.outcomes[name]
            self.say(f"sar-tree run: {name}: Mission {own.status}"
                     + (f": {own.reason}" if own.reason else ""))

    def _cut_short(self, left: list[str], outcome: Outcome) -> Outcome:
        """``outcome`` for every robot still running, and for the run."""
        for name in left:
            self.outcomes[name] = outcome
        return outcome

    def _timed_out(self, left: list[str]) -> Outcome:
        """The timeout's verdict for each robot still running, and the run's."""
        for name in left:
            self.outcomes[name] = timeout_outcome(
                self.config.timeout_s, read_status(self.robot_dir(name)), self.spec,
                self.robot_events[name])
        if not self.named:
            return self.outcomes[""]
        return Outcome("TIMEOUT", EXIT_FAILURE, f"timeout after {self.config.timeout_s:g} s; "
                       f"still running: {', '.join(left)}")

    def stop(self) -> None:
        """Stop every child (the simulator after the runner's cancel) and time it."""
        self._goals.ended()  # what the traces said before the stop does not release it
        # One robot's goal ended: its cancel went through. Named robots: every runner's exit.
        self.stop_s = stop_children(self.children,
                                    released=None if self.named else self._goals.ended)
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
    def own_outcome(self, name: str, outcome: Outcome) -> Outcome:
        """Robot ``name``'s verdict: the run's for the one robot, else its own."""
        return self.outcomes.get(name, outcome) if self.named else outcome

    def record_verdict(self, outcome: Outcome) -> None:
        """Close each robot's event stream with its ``verdict`` (after every child stopped).

        Args:
            outcome: How the mission ended.
        """
        for name in self.robots:
            append_verdict(self.say, self.robot_events[name], self.robot_dir(name),
                           self.own_outcome(name, outcome),
                           wall_s=round(time.monotonic() - self.started, 3), who=name)

    def conclude(self, outcome: Outcome, written: list[Path]) -> int:
        """Print the final lines; return the exit code.

        Args:
            outcome: How the mission ended.
            written: The report files written.
        """
        if self.named:
            return conclude_robots(self, outcome)
        summarise(self.say, self.report_dir, outcome, written, self.stop_s,
                  recording=Path(self.config.record) if self.config.record else None,
                  apps=self.inputs.apps)
        return outcome.exit_code

    def write_report(self, outcome: Outcome) -> list[Path]:
        """Write each robot's report, and named robots' fleet.json and fleet.png.

        Args:
            outcome: How the mission ended.

        Returns:
            The files written.
        """
        wall = (self.completion_wall_s
                if self.config.keep_alive and self.completion_wall_s is not None
                else time.monotonic() - self.started)
        written = [path for name in self.robots
                   for path in robot_report(self, name, self.own_outcome(name, outcome), wall)]
        return written + (robots_page(self, outcome, wall) if self.named else [])
