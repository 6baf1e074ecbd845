"""Log: a line at a level, to the logger and to the event stream, checked like any leaf."""

from __future__ import annotations

import pytest
from py_trees.common import Status

from sar_framework.engine.api import TreeLoadError
from sar_framework.events.emitter import EventEmitter
from sar_framework.events.event import EventKind, MissionEvent


def test_a_log_line_is_an_event_and_the_feedback(sar_leaf) -> None:
    run = sar_leaf("Log", {"message": "shelf (nw) scanned", "level": "warning"})
    seen: list[MissionEvent] = []
    leaf = run.root
    events = EventEmitter([seen.append], nodes={"0": (leaf, "Log")})
    leaf.setup(events=events)
    assert run.tick() == Status.SUCCESS
    assert [(e.kind, e.status, e.message, e.node_kind) for e in seen] == [
        (EventKind.NOTE, "WARNING", "shelf (nw) scanned", "Log")]
    assert run.feedback() == ["shelf (nw) scanned"]


def test_the_level_defaults_to_info(sar_leaf) -> None:
    run = sar_leaf("Log", {"message": "hello"})
    seen: list[MissionEvent] = []
    run.root.setup(events=EventEmitter([seen.append]))
    run.tick()
    assert [e.status for e in seen] == ["INFO"]


def test_a_misspelt_level_is_located_with_a_did_you_mean(sar_tree) -> None:
    with pytest.raises(TreeLoadError) as failed:
        sar_tree("Log: {message: hi, level: warn}")
    assert "tree.yaml:4:" in str(failed.value)
    assert ("'level' must be one of: debug, info, warning, error; got string 'warn'"
            in str(failed.value))
    assert "(did you mean 'warning'?)" in str(failed.value)


def test_a_missing_message_is_located(sar_tree) -> None:
    with pytest.raises(TreeLoadError, match="message"):
        sar_tree("Log: {level: info}")


@pytest.mark.ros
@pytest.mark.parametrize("level", ["info", "warning", "error"])
def test_the_line_goes_to_the_nodes_logger_at_its_level(ros: tuple, level: str,
                                                          capfd: pytest.CaptureFixture) -> None:
    from sar_plugins.log import Log

    node, _executor = ros
    leaf = Log("Log", message=f"said at {level}", level=level)
    leaf.setup(node=node)
    leaf.tick_once()
    err = capfd.readouterr().err
    assert f"[{level.upper() if level != 'warning' else 'WARN'}] " in err, err
    assert f"[sar_test]: said at {level}" in err, err
