"""Leaves for the watch tests: one writes the blackboard, one fails on request."""

from __future__ import annotations

import py_trees

from sar_framework.engine.plugin import Param, leaf

Status = py_trees.common.Status


@leaf(params=[Param("until", int, default=3, minimum=1, description="Ticks before SUCCESS.")])
class CountTicks(py_trees.behaviour.Behaviour):
    """RUNNING until ``until`` ticks, writing the count to ``/ticks_counted``."""

    def __init__(self, name: str, *, until: int) -> None:
        super().__init__(name)
        self.until = until
        self.count = 0
        self.board = self.attach_blackboard_client(name=name)
        self.board.register_key("ticks_counted", access=py_trees.common.Access.WRITE)

    def update(self) -> Status:
        self.count += 1
        self.board.ticks_counted = self.count
        self.feedback_message = f"tick {self.count} of {self.until}"
        return Status.SUCCESS if self.count >= self.until else Status.RUNNING


@leaf(params=[])
class Refuse(py_trees.behaviour.Behaviour):
    """Always FAILURE, with a reason."""

    def update(self) -> Status:
        self.feedback_message = "refused on purpose"
        return Status.FAILURE
