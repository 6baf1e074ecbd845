"""Assertions on a :class:`~sar_framework.testing.trees.TreeRun` with readable failures.

Statuses are given by name (``"RUNNING"``) or as :class:`py_trees.common.Status`; a
failure shows what every node did on every tick.
"""

from __future__ import annotations

import re
from collections.abc import Sequence

from py_trees.common import Status

from sar_framework.testing.trees import TreeRun

#: The characters with a meaning in a regular expression.
_REGEX_CHARACTERS = frozenset(".^$*+?{}[]\\|()")


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


def _message(run: TreeRun, name: str | None, tick: int | None) -> tuple[str, list[str]]:
    """The feedback message of ``name`` at ``tick`` (default: the latest), and all of them."""
    messages = run.feedback(name)
    assert messages, "not ticked yet"
    return (messages[-1] if tick is None else messages[tick - 1]), messages


def assert_feedback(run: TreeRun, pattern: str, name: str | None = None, *,
                    tick: int | None = None) -> None:
    """Assert that the feedback message of ``name`` matches a **regular expression**.

    ``pattern`` is searched in the message with :func:`re.search`, so ``"done (SUCCESS)"``
    does not match the message ``done (SUCCESS)``: parentheses, ``.``, ``*``, ``?``,
    ``+``, ``[``, ``|`` ... are regular-expression syntax. To compare plain text, use
    :func:`assert_feedback_text`.

    Args:
        run: The tree run.
        pattern: A regular expression, searched in the message.
        name: The behaviour (default: the root).
        tick: Which tick's message (1-based); default: the latest.

    Raises:
        AssertionError: With every message the behaviour gave; when the pattern holds
            regular-expression characters, it says so.
    """
    message, messages = _message(run, name, tick)
    try:
        found = re.search(pattern, message)
    except re.error as exc:
        raise AssertionError(f"{pattern!r} is not a regular expression ({exc}); "
                             "assert_feedback_text compares plain text") from None
    if found:
        return
    note = ""
    if any(c in _REGEX_CHARACTERS for c in pattern):
        note = (f"\nnote: {pattern!r} is read as a regular expression and holds "
                "regular-expression characters"
                + (" (as plain text it is in the message)" if pattern in message else "")
                + "; assert_feedback_text compares plain text")
    raise AssertionError(f"{name or run.root.name}: feedback {message!r} does not match "
                         f"{pattern!r}; every tick: {messages}{note}")


def assert_feedback_text(run: TreeRun, text: str, name: str | None = None, *,
                         tick: int | None = None, exact: bool = False) -> None:
    """Assert that the feedback message of ``name`` holds ``text``, as plain text.

    Args:
        run: The tree run.
        text: The text looked for (no character is special).
        name: The behaviour (default: the root).
        tick: Which tick's message (1-based); default: the latest.
        exact: The message must be ``text`` itself, not merely hold it.

    Raises:
        AssertionError: With every message the behaviour gave.
    """
    message, messages = _message(run, name, tick)
    ok = message == text if exact else text in message
    what = "is not" if exact else "does not hold"
    assert ok, (f"{name or run.root.name}: feedback {message!r} {what} {text!r}; "
                f"every tick: {messages}")
