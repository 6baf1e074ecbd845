"""sar-tree run's closing lines and console: what they say is what happened (no ROS)."""

from __future__ import annotations

import json
from pathlib import Path

from sar_framework.orchestrate.outcome import Outcome, exited_children, summarise
from sar_framework.orchestrate.repeats import RepeatCollapser


def _summary(tmp_path: Path, **fields: object) -> list[Path]:
    document = {"wall_duration_s": 9.0, "sim_duration_s": 104.0, "ticks": 208,
                "zones_visited": [], "survivors": [],
                "final_position": {"x": -1.53, "y": -1.0}, "at_base": False, **fields}
    (tmp_path / "mission.json").write_text(json.dumps(document))
    return [tmp_path / "mission.json"]


def _said(tmp_path: Path, written: list[Path], **kwargs: object) -> list[str]:
    lines: list[str] = []
    summarise(lines.append, tmp_path, Outcome("SUCCESS", 0), written, None, **kwargs)
    return lines


def test_a_success_away_from_the_last_goal_is_a_warning(tmp_path: Path) -> None:
    """Regression: 'Mission SUCCESS ... NOT at base' and nothing else said."""
    written = _summary(tmp_path, last_goal={"x": 0.0, "y": 0.0}, at_last_goal=False)
    lines = _said(tmp_path, written)
    assert "sar-tree run: warning: the tree succeeded while the robot is at (-1.53, -1.00), " \
        "away from where its last navigation sent it (0.00, 0.00)" in lines


def test_no_warning_when_the_robot_is_where_it_was_sent(tmp_path: Path) -> None:
    written = _summary(tmp_path, last_goal={"x": -1.5, "y": -1.0}, at_last_goal=True)
    assert not any("run: warning:" in line for line in _said(tmp_path, written))


def test_the_summary_names_the_recording_file(tmp_path: Path) -> None:
    """Regression: the run summary never named the --record file."""
    recording = tmp_path / "mission.mcap"
    recording.write_bytes(b"\x89MCAP0\r\n")
    lines = _said(tmp_path, _summary(tmp_path), recording=recording)
    assert lines[-1] == f"sar-tree run: recording in {recording}"
    missing = _said(tmp_path, _summary(tmp_path), recording=tmp_path / "none.mcap")
    assert missing[-1].endswith("none.mcap (not written)")


def test_a_killed_server_is_worded_plainly() -> None:
    """Regression: 'the detect process had was killed by SIGKILL'."""
    assert exited_children({"detect": -9, "sim": -9, "report": 3}) == [
        "the detect process was killed by SIGKILL", "the report process exited with status 3"]


def test_alternating_decisions_are_collapsed_with_a_count() -> None:
    """Regression: a blocked zone printed 'Returning to base ...' on every cycle."""
    collapser = RepeatCollapser()
    shown: list[str] = []
    for _ in range(300):
        shown += collapser.lines("Returning to base with 3 zone(s) unvisited.")
        shown += collapser.lines("--- Zone 2/4: zone_b (3.00, 3.00) ---")
    shown += collapser.lines("Reached base station.")
    shown += collapser.flush()
    assert shown == [
        "Returning to base with 3 zone(s) unvisited.",
        "--- Zone 2/4: zone_b (3.00, 3.00) ---",
        "(repeated: 'Returning to base with 3 zone(s) unvisited.' 299 more times; "
        "'--- Zone 2/4: zone_b (3.00, 3.00) ---' 299 more times)",
        "Reached base station.",
    ]


def test_distinct_lines_are_all_shown() -> None:
    collapser = RepeatCollapser()
    lines = [f"Reached zone_{c}." for c in "abcdef"]
    assert [out for line in lines for out in collapser.lines(line)] == lines
    assert collapser.flush() == []


def test_a_process_s_repeated_line_counts_whatever_its_numbers() -> None:
    from sar_framework.orchestrate.repeats import numbers_as_one

    collapser = RepeatCollapser()
    shown: list[str] = []
    for goal in range(2, 40, 2):
        for line in (f"sim | Goal {goal} aborted after 0.{goal % 10} s: preempted",
                     "runner | Returning to base with 3 zone(s) unvisited."):
            shown += collapser.lines(line, numbers_as_one(line))
    assert shown == ["sim | Goal 2 aborted after 0.2 s: preempted",
                     "runner | Returning to base with 3 zone(s) unvisited."]
    assert collapser.flush() == [
        "(repeated: 'sim | Goal 2 aborted after 0.2 s: preempted' 18 more times; "
        "'runner | Returning to base with 3 zone(s) unvisited.' 18 more times)"]
