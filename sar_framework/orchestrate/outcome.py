"""Mission outcome of ``sar-tree run``: progress lines, verdict, reason, summary, exit code.

Everything here is decided from the runner's events (:mod:`sar_framework.events`) and its
exit code, never from log text.

Exit codes: 0 the mission reached its declared end with SUCCESS, 1 FAILURE, a timeout or a
failed start-up, 2 bad input (missing tree, a tree or parameter file with errors, a bad
option), 130 interrupted.
"""

from __future__ import annotations

import json
import signal
from collections import Counter
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from sar_framework.app import App
from sar_framework.events.event import CAUSE_KINDS, REASON_KINDS, EventKind, MissionEvent

EXIT_OK = 0
EXIT_FAILURE = 1
EXIT_USAGE = 2
EXIT_INTERRUPTED = 130
RUNNER_EXIT_SIM_TIMEOUT = 4
"""The runner's exit code past its ``sim_timeout_s`` (``sar-tree run --sim-timeout``)."""

PROGRESS_KINDS = frozenset({
    EventKind.NAVIGATION, EventKind.GOAL_REACHED, EventKind.NOTE, EventKind.COMPLETION,
    EventKind.TREE_SWAPPED, EventKind.RELOAD_REFUSED,
})
"""The core's events shown on the console as the mission goes (:func:`progress_line`)."""


def progress_line(event: MissionEvent, apps: Sequence[App] = ()) -> str | None:
    """The console line of an event, or None when it is not a progress event.

    Args:
        event: An event of the runner.
        apps: The tree's apps: each says which of its own events are progress, and how.
    """
    if event.kind in PROGRESS_KINDS:
        return event.message
    for app in apps:
        line = app.progress(event) if app.progress is not None else None
        if line is not None:
            return line
    return None


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


def read_status(report_dir: Path) -> dict[str, Any]:
    """The runner's status file, or ``{}`` when it is missing or unreadable."""
    try:
        return json.loads((report_dir / "status.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}


def last_cause(events: Sequence[MissionEvent]) -> MissionEvent | None:
    """The last failure or timeout event (else the last reason event), or None."""
    reasons = [e for e in events if e.kind in REASON_KINDS]
    causes = [e for e in reasons if e.kind in CAUSE_KINDS]
    return (causes or reasons or [None])[-1]


def failure_reason(events: Sequence[MissionEvent], status: dict[str, Any]) -> str:
    """The last failure the runner emitted, its start-up failure, or its completion."""
    last = last_cause(events)
    if last is not None:
        return f"{last.node_name} [{last.node_uid}] failed: {last.message or 'no reason given'}"
    error = status.get("error")
    if isinstance(error, dict) and error.get("message"):
        return str(error["message"])
    completion = next((e for e in events if e.kind == EventKind.COMPLETION), None)
    return completion.message if completion is not None else "no reason given"


def completion_outcome(completion: MissionEvent, events: Sequence[MissionEvent]) -> Outcome:
    """The outcome the runner's ``completion`` event announced."""
    if completion.status == "SUCCESS":
        return Outcome("SUCCESS", EXIT_OK)
    return Outcome("FAILURE", EXIT_FAILURE, failure_reason(events, {}))


def runner_exit_outcome(code: int, events: Sequence[MissionEvent], status: dict[str, Any],
                        last_error: str, *, spec: Any = None,
                        sim_timeout_s: float | None = None) -> Outcome:
    """The outcome of a runner that exited with ``code``.

    Args:
        code: The runner's exit status.
        events: Every event it emitted.
        status: Its status file (start-up failures; the nodes running at a timeout).
        last_error: Its last warning or error line (quoted for the user, never parsed).
        spec: The tree's spec (names the nodes still running at a timeout), or None.
        sim_timeout_s: The runner's ``sim_timeout_s`` (``--sim-timeout``), or None.
    """
    if code == RUNNER_EXIT_SIM_TIMEOUT and sim_timeout_s:
        return timeout_outcome(sim_timeout_s, status, spec, events, clock="ROS")
    complete = any(e.kind == EventKind.COMPLETION for e in events)
    if code == 0 and not complete:  # stopped by a signal we did not send
        return Outcome("ERROR", EXIT_FAILURE, "the runner was stopped before the mission "
                       "was complete")
    if code == 0:
        return Outcome("SUCCESS", EXIT_OK)
    if code == 1:
        return Outcome("FAILURE", EXIT_FAILURE, failure_reason(events, status))
    if code == 2:
        return Outcome("ERROR", EXIT_USAGE, f"the runner rejected its input: {last_error}")
    return Outcome("ERROR", EXIT_FAILURE, f"the runner exited ({code}): {last_error}")


def exit_words(code: int | None) -> str:
    """``was killed by SIGKILL`` or ``exited with status 3``."""
    if code is not None and code < 0:
        try:
            return f"was killed by {signal.Signals(-code).name}"
        except ValueError:
            return f"was killed by signal {-code}"
    return f"exited with status {code}"


def exited_children(exited: dict[str, int | None]) -> list[str]:
    """``the detect process was killed by SIGKILL`` for each server that ended mid-mission."""
    return [f"the {label} process {exit_words(code)}" for label, code in exited.items()
            if label != "sim"]


def child_exit_outcome(label: str, code: int | None, last_error: str) -> Outcome:
    """The outcome of a run whose simulator (its clock) ended, or a child refused its input.

    Args:
        label: The child.
        code: Its exit status (negative: the signal that killed it).
        last_error: Its last warning or error line, quoted when it exited by itself.
    """
    exit_code = EXIT_USAGE if code == EXIT_USAGE else EXIT_FAILURE
    reason = f"the {label} process {exit_words(code)} mid-mission"
    if code is not None and code >= 0:
        reason += f": {last_error}"
    if label == "sim":
        reason += "; simulated time stopped, so the tree cannot go on"
    return Outcome("ERROR", exit_code, reason)


def timeout_outcome(timeout_s: float, status: dict[str, Any], spec: Any,
                    events: Sequence[MissionEvent], *, clock: str = "") -> Outcome:
    """The outcome of a mission still running after ``timeout_s`` seconds.

    Args:
        timeout_s: The bound.
        status: The runner's status file (its ``running`` nodes are named).
        spec: The tree's spec, or None (nodes are then named by uid).
        events: Every event the runner emitted (the last failure is quoted).
        clock: ``""`` for wall seconds (``--timeout``), ``"ROS"`` for the tree's ROS clock.
    """
    running = list(status.get("running") or [])
    names = {n.uid: n.name for n in spec.nodes()} if spec is not None else {}
    leaves = [u for u in running if not any(o != u and o.startswith(u + ".")
                                            for o in running)]
    where = ", ".join(f"{names.get(u, u)} [{u}]" for u in leaves) or "no node RUNNING"
    failure = last_cause(events)
    last = (f"; last failure: {failure.node_name} [{failure.node_uid}]: "
            f"{failure.message}") if failure else ""
    return Outcome("TIMEOUT", EXIT_FAILURE,
                   f"timeout after {timeout_s:g} s{' of ' + clock + ' time' if clock else ''}; "
                   f"still running: {where}{last}")


def robots_outcome(robots: Mapping[str, Outcome], problems: Sequence[str] = ()) -> Outcome:
    """The verdict of a run of named robots: each robot's, then its apps' problems.

    Args:
        robots: Robot name -> its verdict (the one a single robot gets).
        problems: What the tree's apps found across the robots (each fails the run).

    Returns:
        SUCCESS (exit 0) when every robot succeeded and no app found a problem; INTERRUPTED
        (130) when any robot was; ERROR with exit 2 when a robot's runner rejected its
        input; else FAILURE (1) with every problem in the reason.
    """
    if any(o.status == "INTERRUPTED" for o in robots.values()):
        return Outcome("INTERRUPTED", EXIT_INTERRUPTED, "interrupted (Ctrl-C)")
    found = [f"{name}: {o.status}" + (f" ({o.reason})" if o.reason else "")
             for name, o in robots.items() if o.status != "SUCCESS"] + list(problems)
    if not found:
        return Outcome("SUCCESS", EXIT_OK)
    usage = any(o.exit_code == EXIT_USAGE for o in robots.values())
    return Outcome("ERROR" if usage else "FAILURE", EXIT_USAGE if usage else EXIT_FAILURE,
                   "; ".join(found))


def cut_short(run: Outcome, verdict: Outcome) -> Outcome:
    """The robots' verdict, unless the run was cut short (interrupted, timeout, an error)."""
    if run.status in ("INTERRUPTED", "TIMEOUT") or \
            (run.status == "ERROR" and verdict.status != "INTERRUPTED"):
        return Outcome(run.status, run.exit_code,
                       "; ".join(r for r in (run.reason, verdict.reason) if r))
    return verdict


def where_it_ended(summary: dict[str, Any]) -> str:
    """``final position (0.02, -0.01)`` from a ``mission.json`` document.

    With a base station (an app's ``at_base``), whether the robot ended there:
    ``final position (0.02, -0.01), at base``.
    """
    final = summary.get("final_position")
    if not final:
        return "final position unknown"
    where = ""
    if "at_base" in summary:
        where = ", " + {True: "at base", False: "NOT at base",
                        None: "base unknown"}[summary["at_base"]]
    return f"final position ({final['x']:.2f}, {final['y']:.2f}){where}"


def goal_parts(summary: dict[str, Any]) -> list[str]:
    """``goals reached: 2 of 3; goals not reached: GoShelf (0.00, 3.00)`` from mission.json."""
    goals = summary.get("goals", [])
    reached = [g for g in goals if g.get("result") == "reached"]
    parts = [f"goals reached: {len(reached)} of {len(goals)}"]
    missed = [f"{g['node']} ({g['x']:.2f}, {g['y']:.2f})" for g in goals
              if g.get("result") != "reached"]
    if missed:
        parts.append(f"goals not reached: {', '.join(missed)}")
    return parts


def away_from_goal_warning(summary: dict[str, Any]) -> str | None:
    """The warning for a SUCCESS while the robot is away from its last navigation goal."""
    goal, final = summary.get("last_goal"), summary.get("final_position")
    if summary.get("at_last_goal") is not False or not goal or not final:
        return None
    return (f"warning: the tree succeeded while the robot is at ({final['x']:.2f}, "
            f"{final['y']:.2f}), away from where its last navigation sent it "
            f"({goal['x']:.2f}, {goal['y']:.2f})")


def summarise(say: Callable[[str], None], report_dir: Path, outcome: Outcome,
              written: Sequence[Path], stop_s: float | None, *,
              recording: Path | None = None, apps: Sequence[App] = ()) -> None:
    """Print the final lines: verdict, numbers, failures, where the report is.

    Args:
        say: Prints one line.
        report_dir: The report folder.
        outcome: How the mission ended.
        written: The report files written (mission.json among them, when it was).
        stop_s: Wall seconds the stop took, when known.
        recording: The ``--record`` file, when the mission was recorded.
        apps: The tree's apps: their words replace the list of goals.
    """
    summary: dict[str, Any] = {}
    mission_json = report_dir / "mission.json"
    if mission_json in written:
        summary = json.loads(mission_json.read_text(encoding="utf-8"))
    parts = [f"Mission {outcome.status}"]
    if summary:
        parts.append(f"{summary.get('wall_duration_s', 0):.1f} s wall, "
                     f"{summary.get('sim_duration_s') or 0:.1f} s simulated, "
                     f"{summary.get('ticks', 0)} ticks")
        own = [part for app in apps if app.summary is not None
               for part in app.summary(summary)]
        parts += own or goal_parts(summary)
        parts.append(where_it_ended(summary))
    say("sar-tree run: " + "; ".join(parts))
    if outcome.reason:
        say(f"sar-tree run: {outcome.reason}")
    if outcome.status == "INTERRUPTED" and stop_s is not None:
        say(f"sar-tree run: every process stopped {stop_s:.2f} s after the signal")
    warning = away_from_goal_warning(summary) if outcome.status == "SUCCESS" else None
    if warning:
        say(f"sar-tree run: {warning}")
    if outcome.status == "SUCCESS":
        # A retried leaf can fail the same way several times: one note each, with a count.
        # Retries, skips and cancels were printed as they happened; the causes are noted.
        counts = Counter((f["name"], f["uid"], f.get("what", "failure"), f["message"])
                         for f in summary.get("failures", [])
                         if f.get("what", "failure") in ("failure", "timeout"))
        for (name, uid, what, message), count in counts.items():
            times = f" ({count} times)" if count > 1 else ""
            event = "failed" if what == "failure" else "timed out"
            say(f"sar-tree run: note: {name} [{uid}] {event} on the way{times}: {message}")
    reloads = Counter(r["what"] for r in summary.get("reloads", []))
    if reloads:
        say(f"sar-tree run: tree reloads: {reloads['tree_swapped']} swapped, "
            f"{reloads['reload_refused']} refused (mission.json: reloads)")
    if written:
        say(f"sar-tree run: report in {report_dir}/ "
            f"({', '.join(p.name for p in written)}; child logs *.log)")
    if recording is not None:
        state = "" if recording.exists() else " (not written)"
        say(f"sar-tree run: recording in {recording}{state}")
