"""Assertions on a :class:`~sar_framework.testing.trees.TreeRun` with readable failures.

Statuses are given by name (``"RUNNING"``) or as :class:`py_trees.common.Status`; a
failure shows what every node did on every tick.
"""

from __future__ import annotations

import re
from collections.abc import Sequence

from py_trees.common import Status

from sar_framework.testing.trees import TreeRun


def _status(value: Status | str) -> Status:
    return value if isinstance(value, Status) else Status[value.upper()]


def assert_status(run: TreeRun, expected: Status | str, name: str | None = None) -> None:
    """Assert the current status of ``name`` (default: the root).

    Raises:
        AssertionError: With the tick history.
    """
    behaviour = run.root if name is None else run.node(name)
    wanted = _status(expected)
    assert behaviour.status == wanted, (
        f"{behaviour.name} is {behaviour.status.name}, expected {wanted.name}\n{run.table()}")


def assert_statuses(run: TreeRun, expected: Sequence[Status | str],
                    name: str | None = None) -> None:
    """Assert the status of ``name`` (default: the root) after each tick, in order.

    Raises:
        AssertionError: With the tick history.
    """
    actual = [s.name for s in run.statuses(name)]
    wanted = [_status(s).name for s in expected]
    shown = name or run.root.name
    assert actual == wanted, f"{shown}: {actual}, expected {wanted}\n{run.table()}"


def assert_feedback(run: TreeRun, pattern: str, name: str | None = None, *,
                    tick: int | None = None) -> None:
    """Assert that the feedback message of ``name`` matches a regular expression.

    Args:
        run: The tree run.
        pattern: A regular expression, searched in the message.
        name: The behaviour (default: the root).
        tick: Which tick's message (1-based); default: the latest.

    Raises:
        AssertionError: With every message the behaviour gave.
    """
    messages = run.feedback(name)
    assert messages, "not ticked yet"
    message = messages[-1] if tick is None else messages[tick - 1]
    assert re.search(pattern, message), (
        f"{name or run.root.name}: feedback {message!r} does not match {pattern!r}; "
        f"every tick: {messages}")
