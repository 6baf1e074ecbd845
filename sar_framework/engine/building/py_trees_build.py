"""The builders of py_trees' own kinds (:mod:`~..nodes.node_kinds`) that convert attributes.

Each snake_case kind names its builder in its declaration (``build``): py_trees' class,
called with its attributes, or one of the functions here, called as
``builder(node, children, context)``, which turn a tree file's spelling into py_trees'
arguments (a policy name into ``OneShotPolicy``, seconds into a float). Every
``timeout`` follows the build context's ``clock`` when it has one (:class:`ClockTimeout`).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

import py_trees
from py_trees.common import Status

from sar_framework.engine import compat
from sar_framework.engine.building.control_build import CLOCK_KEY
from sar_framework.engine.spec import NodeSpec

Behaviour = py_trees.behaviour.Behaviour
_Context = Mapping[str, Any]


class ClockTimeout(py_trees.decorators.Timeout):
    """py_trees' ``Timeout``, with ``duration`` measured on ``clock``.

    Args:
        name: The behaviour's name.
        child: The decorated behaviour.
        duration: Seconds on ``clock``.
        clock: Returns the current time in seconds.
    """

    def __init__(self, name: str, child: py_trees.behaviour.Behaviour, duration: float,
                 clock: Callable[[], float]) -> None:
        super().__init__(name=name, child=child, duration=duration)
        self.clock = clock
        self.finish_time = 0.0

    def initialise(self) -> None:
        """Start the bound on this activation."""
        self.finish_time = self.clock() + self.duration
        self.feedback_message = ""

    def update(self) -> Status:
        """FAILURE (halting the child) once the bound passed while the child runs.

        Returns:
            FAILURE on timeout, else the child's status.
        """
        if self.decorated.status == Status.RUNNING and self.clock() > self.finish_time:
            self.feedback_message = "timed out"
            self.decorated.stop(Status.INVALID)
            return Status.FAILURE
        if self.decorated.status == Status.RUNNING:
            self.feedback_message = f"{self.finish_time - self.clock():.2f} s left"
        else:
            self.feedback_message = "child finished before the timeout"
        return self.decorated.status


def sequence(node: NodeSpec, children: list[Behaviour], context: _Context) -> Behaviour:
    """py_trees' ``Sequence`` with the node's ``memory``."""
    return py_trees.composites.Sequence(node.name, node.attrs["memory"], children)


def selector(node: NodeSpec, children: list[Behaviour], context: _Context) -> Behaviour:
    """py_trees' ``Selector`` with the node's ``memory``."""
    return py_trees.composites.Selector(node.name, node.attrs["memory"], children)


def parallel(node: NodeSpec, children: list[Behaviour], context: _Context) -> Behaviour:
    """py_trees' ``Parallel``; ``selected`` names the children its policy waits for."""
    attrs = node.attrs
    wanted = attrs.get("selected") or ()
    selected = [c for name in wanted for c in children if c.name == name]
    policy = compat.parallel_policy(
        attrs["policy"], synchronise=attrs["synchronise"], selected=selected
    )
    return py_trees.composites.Parallel(node.name, policy, children)


def one_shot(node: NodeSpec, children: list[Behaviour], context: _Context) -> Behaviour:
    """py_trees' ``OneShot``; ``policy`` is ``on_completion`` or ``on_successful_completion``."""
    return py_trees.decorators.OneShot(name=node.name, child=children[0],
                                       policy=compat.one_shot_policy(node.attrs["policy"]))


def retry(node: NodeSpec, children: list[Behaviour], context: _Context) -> Behaviour:
    """py_trees' ``Retry``."""
    return py_trees.decorators.Retry(name=node.name, child=children[0],
                                     num_failures=int(node.attrs["num_failures"]))


def repeat(node: NodeSpec, children: list[Behaviour], context: _Context) -> Behaviour:
    """py_trees' ``Repeat``."""
    return py_trees.decorators.Repeat(name=node.name, child=children[0],
                                      num_success=int(node.attrs["num_success"]))


def timeout(node: NodeSpec, children: list[Behaviour], context: _Context) -> Behaviour:
    """py_trees' ``Timeout``; on the context's clock (ROS time) when it has one."""
    duration = float(node.attrs["duration"])
    if CLOCK_KEY in context:
        return ClockTimeout(node.name, children[0], duration, context[CLOCK_KEY])
    return py_trees.decorators.Timeout(name=node.name, child=children[0], duration=duration)


def condition(node: NodeSpec, children: list[Behaviour], context: _Context) -> Behaviour:
    """py_trees' ``Condition``, waiting for the child's ``status``."""
    return py_trees.decorators.Condition(name=node.name, child=children[0],
                                         status=compat.status(node.attrs["status"]))
