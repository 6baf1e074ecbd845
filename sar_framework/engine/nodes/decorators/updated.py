"""BT.CPP 4's entry watchers: SkipUnlessUpdated, WaitValueUpdate and WasEntryUpdated.

Each remembers the version of its entry it last saw. The child is ticked when the
entry was written since (once started, a running child keeps being ticked); otherwise
SkipUnlessUpdated returns SKIPPED and WaitValueUpdate RUNNING. An entry that has no
value counts as not updated. Versions come from the ``Variables`` object's
``version(name)`` (every write through a :class:`~.variables.BlackboardVariables`
counts, as every ``set`` counts in BT.CPP, even of an equal value).

As in BT.CPP, halting these decorators does not halt their child. The leaf
:class:`WasEntryUpdated` answers the same question with SUCCESS or FAILURE.
"""

from __future__ import annotations

import py_trees
from py_trees.common import Status

from sar_framework.engine.nodes.controls.base import Behaviour, BtDecorator, Outcome, Steps
from sar_framework.engine.variables import Variables


class _EntryWatch:
    """The version of ``entry`` last seen, to tell whether it was written since."""

    def __init__(self, name: str, entry: str, variables: Variables) -> None:
        if not callable(getattr(variables, "version", None)):
            raise TypeError(f"'{name}': its variables cannot tell when '{entry}' was written "
                            "(no version(name) method)")
        self.entry = entry
        self.variables = variables
        self.seen = 0

    def updated(self) -> bool:
        """Whether the entry has a value written since the last look (this is a look)."""
        if self.entry not in self.variables:
            return False
        version = self.variables.version(self.entry)  # type: ignore[attr-defined]
        previous, self.seen = self.seen, version
        return version != previous


class _EntryUpdated(BtDecorator):
    """Tick the child only when ``entry`` was written since the last look.

    Args:
        name: The behaviour's name.
        child: The decorated behaviour.
        entry: The watched variable's name.
        variables: Where it lives (must offer ``version(name)``).
    """

    marks_running = False

    not_updated: Outcome

    def __init__(self, name: str, child: Behaviour, entry: str, variables: Variables) -> None:
        self.watch = _EntryWatch(name, entry, variables)
        super().__init__(name, child)
        self.executing = False

    def decorate(self) -> Steps:
        """Tick a running child, or the child if the entry changed; else ``not_updated``."""
        if not self.executing and not self.watch.updated():
            return self.not_updated
        result = yield from self.tick_child()
        self.executing = result is Outcome.RUNNING
        return result

    def halt(self) -> None:
        """Forget that the child was running (BT.CPP leaves the child alone)."""
        self.executing = False


class SkipUnlessUpdated(_EntryUpdated):
    """BT.CPP ``SkipUnlessUpdated``: SKIPPED unless ``entry`` was written since last time."""

    not_updated = Outcome.SKIPPED


class WaitValueUpdate(_EntryUpdated):
    """BT.CPP ``WaitValueUpdate``: RUNNING until ``entry`` was written since last time."""

    not_updated = Outcome.RUNNING


class WasEntryUpdated(py_trees.behaviour.Behaviour):
    """BT.CPP ``WasEntryUpdated``: SUCCESS when ``entry`` was written since the last tick.

    Args:
        name: The behaviour's name.
        entry: The watched variable's name.
        variables: Where it lives (must offer ``version(name)``).
    """

    def __init__(self, name: str, entry: str, variables: Variables) -> None:
        self.watch = _EntryWatch(name, entry, variables)
        super().__init__(name)

    def update(self) -> Status:
        """SUCCESS if the entry has a value written since the last look, else FAILURE."""
        return Status.SUCCESS if self.watch.updated() else Status.FAILURE
