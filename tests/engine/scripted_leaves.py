"""Scripted py_trees leaves for the control tests: each visit returns the next status."""

from __future__ import annotations

import py_trees
from py_trees.common import Status

from sar_framework.engine.nodes.skipping import mark_skipped


class Clock:
    """Seconds that move only when a test sets ``now``."""

    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


class Log:
    """The visits of every scripted leaf, in order (``"NAME STATUS"``)."""

    def __init__(self) -> None:
        self.visits: list[str] = []


class Scripted(py_trees.behaviour.Behaviour):
    """Returns the scripted statuses in turn (the last repeats; none: SUCCESS).

    ``SKIPPED`` returns SUCCESS marked skipped. ``halted`` counts stops while running.
    """

    def __init__(self, name: str, results: list[str], log: Log) -> None:
        super().__init__(name)
        self.results = results or ["SUCCESS"]
        self.log = log
        self.visits = 0
        self.halted = 0

    def update(self) -> Status:
        result = self.results[min(self.visits, len(self.results) - 1)]
        self.visits += 1
        self.log.visits.append(f"{self.name} {result}")
        mark_skipped(self, result == "SKIPPED")
        return Status.SUCCESS if result == "SKIPPED" else Status[result]

    def terminate(self, new_status: Status) -> None:
        if new_status == Status.INVALID and self.status == Status.RUNNING:
            self.halted += 1


def tick(root: py_trees.behaviour.Behaviour) -> Status:
    """Tick ``root`` once; return its status."""
    root.tick_once()
    return root.status
