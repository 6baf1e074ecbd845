"""A leaf with ports for the entries tests: walks along x, writing a real ROS Point."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import py_trees

from sar_framework.engine.plugin import Param, leaf
from sar_framework.engine.ports import InputPort, OutputPort

Status = py_trees.common.Status


@leaf(params=[Param("steps", int, default=3, minimum=1, description="Ticks before SUCCESS.")],
      ports=[InputPort("label", str, description="Shown in the feedback message."),
             OutputPort("where", "geometry_msgs/msg/Point", description="The position."),
             OutputPort("count", int, description="Steps taken so far.")])
class Walk(py_trees.behaviour.Behaviour):
    """RUNNING for ``steps`` ticks, one unit along x per tick."""

    def __init__(self, name: str, *, steps: int, ports: Any) -> None:
        super().__init__(name)
        self.steps = steps
        self.ports = ports
        self.count = 0

    def update(self) -> Status:
        from geometry_msgs.msg import Point

        self.count += 1
        self.ports.set("where", Point(x=float(self.count), y=0.5, z=0.0))
        self.ports.set("count", self.count)
        self.feedback_message = f"{self.ports.get('label')}: step {self.count}"
        return Status.SUCCESS if self.count >= self.steps else Status.RUNNING


@leaf(params=[Param("path", str, description="The file whose existence opens the gate.")])
class WaitForFile(py_trees.behaviour.Behaviour):
    """RUNNING until ``path`` exists, then SUCCESS: the test decides when the tree ends."""

    def __init__(self, name: str, *, path: str) -> None:
        super().__init__(name)
        self.path = Path(path)

    def update(self) -> Status:
        return Status.SUCCESS if self.path.exists() else Status.RUNNING
