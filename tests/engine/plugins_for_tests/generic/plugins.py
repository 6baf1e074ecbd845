"""Small generic test plugins exercising every param feature."""

from __future__ import annotations

import py_trees

from sar_framework.engine.plugin import Param, leaf

Status = py_trees.common.Status


@leaf(
    params=[
        Param("status", str, default="success", enum=("success", "failure", "running"),
              description="The status to return."),
    ]
)
class Fixed(py_trees.behaviour.Behaviour):
    """Return a fixed status."""

    def __init__(self, name: str, *, status: str) -> None:
        super().__init__(name)
        self.fixed = Status[status.upper()]

    def update(self) -> Status:
        return self.fixed


@leaf(
    params=[
        Param("count", int, default=1, minimum=0, maximum=100, description="How many."),
        Param("rate", float, default=1.0, exclusive_minimum=0.0, description="Hz."),
        Param("label", str, description="A required label."),
        Param("loud", bool, default=False, description="Shout."),
        Param("note", str, default=None, description="Optional note."),
        Param("source", ref="Fixed", default=None, description="An optional Fixed leaf."),
    ]
)
class Typed(py_trees.behaviour.Behaviour):
    """Every param type at once."""

    def __init__(self, name: str, **kwargs: object) -> None:
        super().__init__(name)
        self.kwargs = kwargs

    def update(self) -> Status:
        return Status.SUCCESS


@leaf(params=[Param("other", ref="Linked", default=None)])
class Linked(py_trees.behaviour.Behaviour):
    """References another Linked leaf (to make reference cycles)."""

    def __init__(self, name: str, *, other: object) -> None:
        super().__init__(name)
        self.other = other

    def update(self) -> Status:
        return Status.SUCCESS


@leaf()
class Exploding(py_trees.behaviour.Behaviour):
    """Its constructor raises."""

    def __init__(self, name: str) -> None:
        raise RuntimeError("boom")

    def update(self) -> Status:
        return Status.SUCCESS


@leaf()
class Tick(py_trees.behaviour.Behaviour):
    """A minimal SUCCESS leaf (for benchmarks and big trees)."""

    def update(self) -> Status:
        return Status.SUCCESS
