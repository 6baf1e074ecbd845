"""``sar-tree run``'s verdict, reasons and progress lines come from events, not log text."""

from __future__ import annotations

from sar_plugins.sar.app import APP as SAR
from sar_plugins.sar.events import SarKind

from sar_framework.events.event import EventKind, MissionEvent
from sar_framework.orchestrate.outcome import (
    EXIT_FAILURE,
    EXIT_OK,
    completion_outcome,
    progress_line,
    runner_exit_outcome,
    timeout_outcome,
)

STARTED = MissionEvent(EventKind.STARTED, seq=1, message="Ticking t.yaml")
FAILED = MissionEvent(EventKind.FAILURE, seq=2, node_name="DetectSurvivor", node_uid="0.1",
                      message="/detect_survivor service not available after 1.5 s")
CANCELLED = MissionEvent(EventKind.CANCEL, seq=3, node_name="Wait", node_uid="0.2",
                         message="halted")


def _completion(status: str, message: str = "whatever the runner says") -> MissionEvent:
    return MissionEvent(EventKind.COMPLETION, seq=9, status=status, message=message)


def test_the_verdict_is_the_completion_events_status_whatever_its_words() -> None:
    assert completion_outcome(_completion("SUCCESS", "Mission failed!"), []).status == "SUCCESS"
    failed = completion_outcome(_completion("FAILURE", "Mission complete."), [FAILED])
    assert (failed.status, failed.exit_code) == ("FAILURE", EXIT_FAILURE)
    assert failed.reason == ("DetectSurvivor [0.1] failed: /detect_survivor service not "
                             "available after 1.5 s")


def test_a_cause_is_preferred_to_what_the_tree_did_about_it() -> None:
    outcome = runner_exit_outcome(1, [STARTED, FAILED, CANCELLED, _completion("FAILURE")],
                                  {}, "last log line")
    assert outcome.reason.startswith("DetectSurvivor [0.1] failed")
    only_cancel = runner_exit_outcome(1, [CANCELLED, _completion("FAILURE")], {}, "")
    assert only_cancel.reason == "Wait [0.2] failed: halted"


def test_a_runner_that_exits_0_without_a_completion_event_was_stopped() -> None:
    assert runner_exit_outcome(0, [STARTED, _completion("SUCCESS")], {}, "").exit_code == EXIT_OK
    stopped = runner_exit_outcome(0, [STARTED], {"complete": True}, "Mission complete.")
    assert (stopped.status, stopped.exit_code) == ("ERROR", EXIT_FAILURE)


def test_a_start_up_failure_comes_from_the_status_file_not_a_log_line() -> None:
    status = {"error": {"step": "setup", "message": "tree setup timed out"}}
    assert runner_exit_outcome(1, [], status, "a reworded line").reason == "tree setup timed out"


def test_a_timeout_names_the_last_failure_event() -> None:
    outcome = timeout_outcome(30.0, {"running": ["0", "0.2"]}, None, [FAILED])
    assert outcome.status == "TIMEOUT"
    assert outcome.reason == ("timeout after 30 s; still running: 0.2 [0.2]; last failure: "
                              "DetectSurvivor [0.1]: /detect_survivor service not available "
                              "after 1.5 s")


def test_progress_lines_are_the_events_that_tell_the_mission() -> None:
    shown = MissionEvent(SarKind.ZONE_REACHED, fields={"zone_id": "zone_a"},
                         message="Reached zone_a.")
    assert progress_line(shown, [SAR]) == "Reached zone_a."
    assert progress_line(shown) is None  # a tree without the app emits none of them
    refused = MissionEvent(SarKind.SURVIVOR_REFUSED, fields={"survivor_id": "survivor_2"},
                           message="refuse_all is set")
    assert progress_line(refused, [SAR]) == \
        "Report for survivor_2 refused by base: refuse_all is set"
    goal = MissionEvent(EventKind.GOAL_REACHED, message="goal (1.00, 2.00) reached")
    assert progress_line(goal) == "goal (1.00, 2.00) reached"
    for quiet in (STARTED, FAILED, MissionEvent(EventKind.STATUS, message="RUNNING"),
                  MissionEvent(EventKind.VERDICT, message="Mission SUCCESS")):
        assert progress_line(quiet, [SAR]) is None


def test_a_runner_past_its_sim_timeout_is_a_timeout_in_ros_time() -> None:
    outcome = runner_exit_outcome(4, [FAILED], {"running": ["0", "0.2"]}, "a log line",
                                  sim_timeout_s=45.0)
    assert (outcome.status, outcome.exit_code) == ("TIMEOUT", EXIT_FAILURE)
    assert outcome.reason.startswith("timeout after 45 s of ROS time; still running: "
                                     "0.2 [0.2]; last failure: DetectSurvivor [0.1]")
    # Without a bound asked for, exit 4 is just an unexpected exit code.
    assert runner_exit_outcome(4, [], {}, "a log line").status == "ERROR"
