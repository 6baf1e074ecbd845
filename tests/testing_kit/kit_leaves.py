"""A leaf that reads the py_trees blackboard, to test the kit's scripted blackboard."""

from __future__ import annotations

import py_trees
from py_trees.common import Access, Status

from sar_framework.engine.plugin import leaf


@leaf()
class LevelAboveZero(py_trees.behaviour.Behaviour):
    """SUCCESS when the blackboard's /level is above zero, else FAILURE."""

    def __init__(self, name: str) -> None:
        super().__init__(name)
        self.board = self.attach_blackboard_client(name=name)
        self.board.register_key("/level", access=Access.READ)

    def update(self) -> Status:
        level = self.board.get("/level")
        self.feedback_message = f"level {level}"
        return Status.SUCCESS if level > 0 else Status.FAILURE
