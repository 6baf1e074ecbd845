"""A control node and a decorator added by a plugin, without touching the engine."""

from __future__ import annotations

import py_trees
from py_trees.common import Status

from sar_framework.engine.kind_plugin import control_kind, decorator_kind, node_kind
from sar_framework.engine.nodes.kind_model import Attr, AttrType


@node_kind(control_kind(
    "Majority", "Every child each tick; SUCCESS once more than half succeeded, FAILURE once "
    "that cannot happen.",
    Attr("quorum", AttrType.INTEGER, default=0, minimum=0,
         description="Successes needed; 0: more than half of the children.")))
class Majority(py_trees.composites.Composite):
    """Ticks every unfinished child; succeeds on a quorum of successes."""

    def __init__(self, name: str, children: list[py_trees.behaviour.Behaviour], *,
                 quorum: int) -> None:
        super().__init__(name, children)
        self.quorum = quorum or len(children) // 2 + 1

    def tick(self):  # type: ignore[no-untyped-def]
        """Tick the unfinished children, then settle on the counts."""
        if self.status != Status.RUNNING:
            self.initialise()
            for child in self.children:
                child.stop(Status.INVALID)
        for child in self.children:
            if child.status in (Status.SUCCESS, Status.FAILURE):
                continue
            yield from child.tick()
        successes = sum(c.status == Status.SUCCESS for c in self.children)
        failures = sum(c.status == Status.FAILURE for c in self.children)
        if successes >= self.quorum:
            self.stop(Status.SUCCESS)
        elif len(self.children) - failures < self.quorum:
            self.stop(Status.FAILURE)
        else:
            self.status = Status.RUNNING
        yield self

    def stop(self, new_status: Status = Status.INVALID) -> None:
        """Halt the children still running."""
        for child in self.children:
            if child.status == Status.RUNNING:
                child.stop(Status.INVALID)
        self.status = new_status
        super().stop(new_status)


@node_kind(decorator_kind(
    "Twice", "Tick a succeeding child until it succeeded times times; a failure fails.",
    Attr("times", AttrType.INTEGER, default=2, minimum=1,
         description="Successes needed.")), spellings=("RepeatTwice",))
class Twice(py_trees.decorators.Decorator):
    """RUNNING until the child succeeded ``times`` times."""

    def __init__(self, name: str, child: py_trees.behaviour.Behaviour, *, times: int) -> None:
        super().__init__(name=name, child=child)
        self.times, self.done = times, 0

    def initialise(self) -> None:
        """Count from zero on each activation."""
        self.done = 0

    def update(self) -> Status:
        """Count the child's successes."""
        if self.decorated.status == Status.SUCCESS:
            self.done += 1
            return Status.SUCCESS if self.done >= self.times else Status.RUNNING
        return self.decorated.status
