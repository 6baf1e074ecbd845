"""One ``sar-tree run --robots N``/``--fleet FILE``: a fleet's children, verdicts, report.

:class:`FleetOrchestrator` is the one-robot :class:`~.orchestrator.Orchestrator` with a
runner per robot: it follows each robot's events (``RUN/<name>/events.jsonl``), waits until
every runner has ended (or the timeout, a Ctrl-C, the simulator's end), gives each robot
its verdict as one robot gets it (:mod:`.outcome`), writes each robot's report into its
folder (``mission.json``, ``mission.png``, ``tree.svg``), then the fleet's verdict
(:mod:`.fleet_outcome`), ``fleet.json`` and ``fleet.png`` (:mod:`sar_framework.report_fleet`).
"""

from __future__ import annotations

import json
import threading
import time
from pathlib import Path
from typing import IO

from sar_framework.events.event import MissionEvent
from sar_framework.events.jsonl import (
    EVENTS_FILE,
    EventFileFollower,
    read_json_lines,
)
from sar_framework.mission.fleet_processes import COORDINATOR_EVENTS_FILE
from sar_framework.orchestrate.config import ChildSpec, child_specs, write_fleet_file
from sar_framework.orchestrate.fleet_outcome import (
    fleet_document,
    fleet_outcome,
    zone_searchers,
)
from sar_framework.orchestrate.inputs import CheckedInputs
from sar_framework.orchestrate.options import RunConfig
from sar_framework.orchestrate.orchestrator import POLL_S, Orchestrator
from sar_framework.orchestrate.outcome import (
    EXIT_FAILURE,
    EXIT_INTERRUPTED,
    EXIT_OK,
    EXIT_USAGE,
    Outcome,
    child_exit_outcome,
    exit_words,
    progress_line,
    read_status,
    runner_exit_outcome,
    timeout_outcome,
)

ROBOT_FILES = ("status.json", EVENTS_FILE, "trace.jsonl", "mission.json", "mission.png",
               "tree.svg", "detect.log", "runner.log")
FLEET_FILES = ("fleet.json", "fleet.png", COORDINATOR_EVENTS_FILE, "coordinator.log")


class FleetOrchestrator(Orchestrator):
    """A fleet's ``sar-tree run``: one simulator, the base, the coordinator, N runners.

    Args:
        config: The checked configuration (``robots`` or ``fleet``).
        inputs: What the checks found, ``inputs.fleet`` the robots.
        out: Where progress goes (stdout by default).
    """

    def __init__(self, config: RunConfig, inputs: CheckedInputs,
                 out: IO[str] | None = None) -> None:
        super().__init__(config, inputs, out)
        self.robots = {robot.name: robot for robot in inputs.fleet}
        self.robot_events: dict[str, list[MissionEvent]] = {name: [] for name in self.robots}
        self._followers = {name: EventFileFollower(self.robot_dir(name) / EVENTS_FILE)
                           for name in self.robots}
        self.outcomes: dict[str, Outcome] = {}
        self.fleet: Outcome | None = None
        self.summaries: dict[str, dict] = {}

    def robot_dir(self, name: str) -> Path:
        """``RUN/<name>``: the robot's status, events, trace, logs and report."""
        return self.report_dir / name

    def prepare(self) -> None:
        """The one-robot clean-up, each robot's folder, the fleet's files, the fleet file."""
        super().prepare()
        for name in FLEET_FILES:
            (self.report_dir / name).unlink(missing_ok=True)
        for robot in self.robots:
            self.robot_dir(robot).mkdir(exist_ok=True)
            for name in ROBOT_FILES:
                (self.robot_dir(robot) / name).unlink(missing_ok=True)
        fleet = write_fleet_file(self.config, self.report_dir, self.inputs.fleet)
        self.say(f"sar-tree run: a fleet of {len(self.robots)} ({', '.join(self.robots)}) "
                 f"from {fleet}; zones " + ("shared out by the zone coordinator"
                                            if self.inputs.coordinator
                                            else "walked by every robot (no coordinator)"))

    def child_specs(self) -> list[ChildSpec]:
        """The fleet's processes (:mod:`sar_framework.mission.fleet_processes`)."""
        return child_specs(self.config, self.report_dir, self.inputs.places,
                           fleet=self.inputs.fleet, coordinator=self.inputs.coordinator,
                           zone_order=list(self.inputs.runner_values.get("zone_order") or []),
                           apps=self.inputs.apps)

    def take_events(self) -> None:
        """Read every robot's new events; show the progress ones under the robot's name."""
        for name, follower in self._followers.items():
            for event in follower.poll():
                self.robot_events[name].append(event)
                self.events.append(event)
                line = progress_line(event, self.inputs.apps)
                if line is not None:
                    self.show(time.monotonic() - self.started, name, line)
        if self.events:
            self.import_report_libraries()

    def wait(self, interrupt: threading.Event) -> Outcome:
        """Wait until every runner ended, the simulator ends, the timeout, or Ctrl-C.

        Each robot's verdict goes into :attr:`outcomes`.

        Returns:
            TIMEOUT or INTERRUPTED when the run was cut short (their line is printed),
            else a placeholder SUCCESS: the fleet's verdict comes with the reports.
        """
        runners = {name: self.child(f"{name}/runner") for name in self.robots}
        deadline = self.started + self.config.timeout_s
        while True:
            self.take_events()
            left = [name for name in self.robots if name not in self.outcomes]
            if interrupt.is_set():
                for name in left:
                    self.outcomes[name] = Outcome("INTERRUPTED", EXIT_INTERRUPTED,
                                                  "interrupted (Ctrl-C)")
                return Outcome("INTERRUPTED", EXIT_INTERRUPTED, "interrupted (Ctrl-C)")
            for name in left:
                runner = runners[name]
                if runner is None:  # never started: nothing to wait for
                    self.outcomes[name] = Outcome("ERROR", EXIT_FAILURE, "no runner started")
                    continue
                code = runner.poll()
                if code is None:
                    continue
                runner.finish_reading()
                self.take_events()
                self.outcomes[name] = runner_exit_outcome(
                    code, self.robot_events[name], read_status(self.robot_dir(name)),
                    self.last_error(runner.label), spec=self.spec,
                    sim_timeout_s=self.config.sim_timeout_s)
                self.say(f"sar-tree run: {name}: Mission {self.outcomes[name].status}"
                         + (f": {self.outcomes[name].reason}" if self.outcomes[name].reason
                            else ""))
            left = [name for name in self.robots if name not in self.outcomes]
            if not left:
                return Outcome("SUCCESS", EXIT_OK)
            for child in self.children:
                if child.label.endswith("/runner") or child.label in self.exited \
                        or child.poll() is None:
                    continue
                child.finish_reading()
                self.exited[child.label] = child.poll()
                if child.label == "sim" or child.poll() == EXIT_USAGE:
                    ended = child_exit_outcome(child.label, child.poll(),
                                               self.last_error(child.label))
                    for name in left:
                        self.outcomes[name] = ended
                    return ended
                self.say(f"sar-tree run: the {child.label} process {exit_words(child.poll())} "
                         "mid-mission; the fleet goes on without it")
            if time.monotonic() > deadline:
                for name in left:
                    self.outcomes[name] = timeout_outcome(
                        self.config.timeout_s, read_status(self.robot_dir(name)), self.spec,
                        self.robot_events[name])
                return Outcome("TIMEOUT", EXIT_FAILURE,
                               f"timeout after {self.config.timeout_s:g} s; still running: "
                               f"{', '.join(left)}")
            time.sleep(POLL_S)

    def stop(self) -> None:
        """Stop every child: the runners and servers first, the simulator after them."""
        from sar_framework.orchestrate.supervise import stop_children

        self.stop_s = stop_children(self.children)
        self.take_events()
        self.flush_repeats()

    def record_verdict(self, outcome: Outcome) -> None:
        """Close each robot's event stream with its own ``verdict``."""
        for name in self.robots:
            self.append_verdict(self.robot_events[name], self.robot_dir(name),
                                self.outcomes.get(name, outcome), who=name)

    def write_report(self, outcome: Outcome) -> list[Path]:
        """Each robot's report in its folder, then ``fleet.json`` and ``fleet.png``."""
        from sar_framework.report import MissionInputs, write_report

        written: list[Path] = []
        wall = time.monotonic() - self.started
        for name, robot in self.robots.items():
            own = self.outcomes.get(name, outcome)
            inputs = MissionInputs(
                report_dir=self.robot_dir(name), tree=self.config.tree,
                params_file=self.config.params, spec=self.spec, outcome=own.status,
                reason=own.reason, wall_duration_s=wall,
                blocked_areas=self.inputs.blocked_areas,
                base={"x": robot.x, "y": robot.y, "yaw": robot.yaw})
            try:
                written += write_report(inputs)
                self.summaries[name] = json.loads(
                    (self.robot_dir(name) / "mission.json").read_text(encoding="utf-8"))
            except Exception as err:  # a report problem must not hide the verdict
                self.say(f"sar-tree run: warning: {name}: could not write the report: "
                         f"{type(err).__name__}: {err}")
                self.summaries[name] = {}
        return written + self._write_fleet(outcome, wall)

    def _write_fleet(self, outcome: Outcome, wall: float) -> list[Path]:
        events_path = self.report_dir / COORDINATOR_EVENTS_FILE
        bids = read_json_lines(events_path) if self.inputs.coordinator else None
        searched = zone_searchers(list(self.inputs.places), self.summaries, bids)
        self.outcomes = {name: self.outcomes[name] for name in self.robots
                         if name in self.outcomes}  # fleet order, for fleet.json's colours
        verdict = fleet_outcome(self.outcomes, self.summaries, searched,
                                once=self.inputs.coordinator)
        if outcome.status in ("INTERRUPTED", "TIMEOUT") or \
                (outcome.status == "ERROR" and verdict.status != "INTERRUPTED"):
            verdict = Outcome(outcome.status, outcome.exit_code,
                              "; ".join(r for r in (outcome.reason, verdict.reason) if r))
        self.fleet = verdict
        document = fleet_document(verdict, self.outcomes, self.summaries, searched,
                                  coordinator=self.inputs.coordinator, wall_duration_s=wall)
        fleet_json = self.report_dir / "fleet.json"
        fleet_json.write_text(json.dumps(document, indent=2) + "\n", encoding="utf-8")
        written = [fleet_json]
        try:
            from sar_framework.report_fleet import draw_fleet

            written.append(draw_fleet(self.report_dir, document, self.config.params,
                                      bids or [], self.report_dir / "fleet.png"))
        except Exception as err:
            self.say(f"sar-tree run: warning: could not draw fleet.png: "
                     f"{type(err).__name__}: {err}")
        return written

    def conclude(self, outcome: Outcome, written: list[Path]) -> int:
        """Print a line per robot and the fleet's; return the fleet's exit code."""
        fleet = self.fleet or outcome
        for name in self.robots:
            summary = self.summaries.get(name, {})
            own = self.outcomes.get(name, outcome)
            zones = ", ".join(dict.fromkeys(z["id"] for z in summary.get("zones_visited", [])))
            sim = summary.get("sim_duration_s") or 0.0
            home = {True: "home", False: "NOT home", None: "home unknown"}[summary.get("at_base")]
            self.say(f"sar-tree run: {name}: {own.status}; {sim:.1f} s simulated; zones "
                     f"visited: {zones or 'none'}; {home}")
        self.say(f"sar-tree run: Fleet {fleet.status}"
                 + (f": {fleet.reason}" if fleet.reason else ""))
        if fleet.status == "INTERRUPTED" and self.stop_s is not None:
            self.say(f"sar-tree run: every process stopped {self.stop_s:.2f} s after the signal")
        self.say(f"sar-tree run: report in {self.report_dir}/ (fleet.json, fleet.png; each "
                 "robot's mission.json, mission.png and logs in its folder)")
        return fleet.exit_code
