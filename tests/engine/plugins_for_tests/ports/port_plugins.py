"""Small test plugins that declare ports: plan into a path, follow it, literals of each type."""

from __future__ import annotations

from typing import Any

import py_trees

from sar_framework.engine.plugin import Param, leaf
from sar_framework.engine.ports import BidirectionalPort, InputPort, OutputPort

Status = py_trees.common.Status


@leaf(ports=[
    InputPort("start", "geometry_msgs/msg/Point", default="{start}", description="From here."),
    InputPort("goal", "geometry_msgs/msg/Point", description="To here."),
    OutputPort("path", "nav_msgs/msg/Path", description="The waypoints, start excluded."),
])
class Plan(py_trees.behaviour.Behaviour):
    """Plan a straight path of unit steps from start to goal (points are (x, y) tuples)."""

    def __init__(self, name: str, *, ports: Any) -> None:
        super().__init__(name)
        self.ports = ports

    def update(self) -> Status:
        (x, y), (gx, gy) = self.ports.get("start"), self.ports.get("goal")
        path = []
        while (x, y) != (gx, gy):
            x += (gx > x) - (gx < x)
            y += (gy > y) - (gy < y)
            path.append((x, y))
        self.ports.set("path", path)
        return Status.SUCCESS


@leaf(ports=[
    InputPort("path", "nav_msgs/msg/Path", description="Waypoints to follow."),
    BidirectionalPort("pose", "geometry_msgs/msg/Point", default="{start}",
                      description="Where the robot is; moved one waypoint per tick."),
    OutputPort("steps", int, description="Waypoints reached so far."),
])
class Follow(py_trees.behaviour.Behaviour):
    """Follow a path one waypoint per tick: RUNNING until the last one."""

    def __init__(self, name: str, *, ports: Any) -> None:
        super().__init__(name)
        self.ports = ports
        self.index = 0

    def initialise(self) -> None:
        self.index = 0

    def update(self) -> Status:
        path = self.ports.get("path")
        if self.index >= len(path):
            return Status.SUCCESS
        self.ports.set("pose", path[self.index])
        self.index += 1
        self.ports.set("steps", self.index)
        return Status.RUNNING if self.index < len(path) else Status.SUCCESS


@leaf(
    params=[Param("label", str, default="x", description="A plain param.")],
    ports=[
        InputPort("text", str, default="hi"),
        InputPort("times", int, default=1),
        InputPort("rate", float, default=1.0),
        InputPort("loud", bool, default=False),
        InputPort("items", list, default=[]),
        InputPort("anything", object, default=None),
    ],
)
class Say(py_trees.behaviour.Behaviour):
    """Read every basic port type; remember what it read."""

    def __init__(self, name: str, *, label: str, ports: Any) -> None:
        super().__init__(name)
        self.ports = ports
        self.label = label
        self.heard: dict[str, Any] = {}

    def update(self) -> Status:
        for name in ("text", "times", "rate", "loud", "items", "anything"):
            self.heard[name] = self.ports.get(name)
        return Status.SUCCESS


@leaf(ports=[OutputPort("value", int, description="Written each tick."),
             InputPort("number", int, default=7)])
class Emit(py_trees.behaviour.Behaviour):
    """Write its number to an int entry."""

    def __init__(self, name: str, *, ports: Any) -> None:
        super().__init__(name)
        self.ports = ports

    def update(self) -> Status:
        self.ports.set("value", self.ports.get("number"))
        return Status.SUCCESS


@leaf(ports=[InputPort("value", float), OutputPort("seen", float)])
class Gauge(py_trees.behaviour.Behaviour):
    """Read a float entry and copy it out."""

    def __init__(self, name: str, *, ports: Any) -> None:
        super().__init__(name)
        self.ports = ports

    def update(self) -> Status:
        self.ports.set("seen", self.ports.get("value"))
        return Status.SUCCESS


@leaf(ports=[InputPort("word", str)])
class Spell(py_trees.behaviour.Behaviour):
    """Read a string entry."""

    def __init__(self, name: str, *, ports: Any) -> None:
        super().__init__(name)
        self.ports = ports

    def update(self) -> Status:
        self.ports.get("word")
        return Status.SUCCESS
