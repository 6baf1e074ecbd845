"""Test plugins for hot swaps: a leaf that works for some ticks, and one that reads it."""

from __future__ import annotations

from typing import Any

import py_trees

from sar_framework.engine.plugin import Param, leaf
from sar_framework.engine.ports import InputPort, OutputPort

Status = py_trees.common.Status

#: Every halt of a RUNNING Work leaf (its name), as a parent's stop(INVALID) causes.
HALTED: list[str] = []


@leaf(params=[Param("ticks", int, default=2, minimum=1, description="RUNNING ticks."),
              Param("note", str, default="", description="Free text.")],
      ports=[OutputPort("done", int, description="How many times it succeeded."),
             InputPort("seed", int, default=0, description="Added to the count.")])
class Work(py_trees.behaviour.Behaviour):
    """RUNNING for ``ticks`` ticks, then SUCCESS; counts its ticks across runs."""

    def __init__(self, name: str, *, ticks: int, note: str, ports: Any) -> None:
        super().__init__(name)
        self.ticks = ticks
        self.note = note
        self.ports = ports
        self.left = 0
        self.total = 0
        self.successes = 0

    def initialise(self) -> None:
        self.left = self.ticks

    def update(self) -> Status:
        self.total += 1
        if self.left > 0:
            self.left -= 1
            return Status.RUNNING
        self.successes += 1
        self.ports.set("done", self.successes + self.ports.get("seed"))
        return Status.SUCCESS

    def terminate(self, new_status: Status) -> None:
        if new_status == Status.INVALID and self.status == Status.RUNNING:
            HALTED.append(self.name)


@leaf(params=[Param("work", ref="Work", description="The leaf to read.")])
class Peek(py_trees.behaviour.Behaviour):
    """SUCCESS once the referenced Work leaf has ticked at least once."""

    def __init__(self, name: str, *, work: Work) -> None:
        super().__init__(name)
        self.work = work

    def update(self) -> Status:
        return Status.SUCCESS if self.work.total else Status.FAILURE


@leaf(context=["zone_manager"])
class UsesContext(py_trees.behaviour.Behaviour):
    """Holds the context object it was given."""

    def __init__(self, name: str, *, zone_manager: Any) -> None:
        super().__init__(name)
        self.zone_manager = zone_manager

    def update(self) -> Status:
        return Status.SUCCESS
