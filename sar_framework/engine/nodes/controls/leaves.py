"""BT.CPP 4's built-in leaves.

AlwaysSuccess, AlwaysFailure, Sleep, SetBlackboard and UnsetBlackboard.

The blackboard leaves read and write through a :class:`~.variables.Variables` object,
so they work on py_trees' blackboard (through ``BlackboardVariables``) or on anything
else that offers the same four methods.
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from typing import Any

import py_trees
from py_trees.common import Status

from sar_framework.engine.nodes.controls.base import Clock
from sar_framework.engine.nodes.controls.read_ports import ReadsPorts
from sar_framework.engine.variables import Variables


class AlwaysSuccess(py_trees.behaviour.Behaviour):
    """BT.CPP ``AlwaysSuccess``: SUCCESS at once."""

    def update(self) -> Status:
        """Succeed."""
        return Status.SUCCESS


class AlwaysFailure(py_trees.behaviour.Behaviour):
    """BT.CPP ``AlwaysFailure``: FAILURE at once."""

    def update(self) -> Status:
        """Fail."""
        return Status.FAILURE


class Sleep(ReadsPorts, py_trees.behaviour.Behaviour):
    """BT.CPP ``Sleep``: RUNNING for ``msec`` milliseconds, then SUCCESS (0: SUCCESS at once).

    Like every BT.CPP ``StatefulActionNode``, once it succeeded it keeps returning
    SUCCESS without starting again until its parent resets it (to IDLE).

    Args:
        name: The behaviour's name.
        msec: Milliseconds to wait.
        clock: Returns the time in seconds (default ``time.monotonic``).
    """

    def __init__(self, name: str, msec: int, clock: Clock = time.monotonic) -> None:
        super().__init__(name)
        self.duration = msec / 1000.0
        self.clock = clock
        self.started_at = 0.0
        self.starting = True
        #: The status BT.CPP would show (INVALID: IDLE); reset by the parent.
        self.bt_status = Status.INVALID

    def read_port(self, port: str, value: int) -> None:
        """Take ``msec`` read from its entry."""
        self.duration = value / 1000.0

    def tick(self) -> Iterator[py_trees.behaviour.Behaviour]:
        """Read ``msec`` when BT.CPP does (on starting), then tick as py_trees does."""
        self.read_ports()
        return (yield from super().tick())

    def initialise(self) -> None:
        """Start the wait (unless it already succeeded and was not reset)."""
        if self.bt_status != Status.SUCCESS:
            self.started_at = self.clock()
            self.starting = True

    def update(self) -> Status:
        """RUNNING on the first tick (unless msec is 0), then until the time passed."""
        if self.bt_status == Status.SUCCESS:
            return Status.SUCCESS
        starting, self.starting = self.starting, False
        if self.duration > 0 and (starting or self.clock() - self.started_at < self.duration):
            self.feedback_message = "sleeping"
            self.bt_status = Status.RUNNING
        else:
            self.bt_status = Status.SUCCESS
        status = self.bt_status
        if self.parent is None and status == Status.SUCCESS:
            self.bt_status = Status.INVALID  # BT.CPP's tickRoot resets a finished root
        return status

    def terminate(self, new_status: Status) -> None:
        """Halted or reset: back to IDLE."""
        if new_status == Status.INVALID:
            self.bt_status = Status.INVALID


def entry_name(text: str) -> str | None:
    """The entry a port text names (``{goal}``, ``{@goal}`` -> ``goal``), or None."""
    text = text.strip()
    if len(text) > 2 and text[0] == "{" and text[-1] == "}":
        return text[1:-1].lstrip("@") or None
    return None


class SetBlackboard(py_trees.behaviour.Behaviour):
    """BT.CPP ``SetBlackboard``: write ``value`` (a literal or an entry's value) to ``output_key``.

    Args:
        name: The behaviour's name.
        value: The literal to write (a string as written, or a value), or ``"{entry}"``
            to copy that entry's value.
        output_key: The name of the variable written.
        variables: Where both live.

    Raises:
        KeyError: On update, ``value`` names an entry that has no value.
    """

    def __init__(self, name: str, value: Any, output_key: str, variables: Variables) -> None:
        super().__init__(name)
        self.value = value
        self.source = entry_name(value) if isinstance(value, str) else None
        self.output_key = output_key
        self.variables = variables

    def update(self) -> Status:
        """Write the value; SUCCESS."""
        if self.source is None:
            value = self.value
        elif self.source in self.variables:
            value = self.variables.get(self.source)
        else:
            raise KeyError(f"SetBlackboard '{self.name}': the entry '{self.source}' named "
                           "by value has no value")
        self.variables.set(self.output_key, value)
        return Status.SUCCESS


class UnsetBlackboard(py_trees.behaviour.Behaviour):
    """BT.CPP ``UnsetBlackboard``: remove the variable ``key``; SUCCESS.

    Args:
        name: The behaviour's name.
        key: The name of the variable removed.
        variables: Where it lives.
    """

    def __init__(self, name: str, key: str, variables: Variables) -> None:
        super().__init__(name)
        self.key = key
        self.variables = variables

    def update(self) -> Status:
        """Remove the variable; SUCCESS."""
        self.variables.unset(self.key)
        return Status.SUCCESS
