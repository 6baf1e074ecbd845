"""Leaves without ROS: a plain action, a condition, and a stateful action.

* :class:`Leaf`: a py_trees behaviour whose declared params and context objects arrive as
  attributes; override ``update()`` (and ``initialise()``...) as in py_trees.
* :class:`Condition`: answers in the tick through :meth:`Condition.check`; never RUNNING.
* :class:`StatefulLeaf`: long work without ROS, on BehaviorTree.CPP's
  ``StatefulActionNode`` moments: :meth:`StatefulLeaf.on_start` on the first tick of an
  activation, :meth:`StatefulLeaf.on_running` on the next ones, :meth:`StatefulLeaf.on_halted`
  when it is stopped while RUNNING.
"""

from __future__ import annotations

from typing import Any

import py_trees
from py_trees.common import Status

from sar_framework.leaves.declared import keep_declared


class Leaf(py_trees.behaviour.Behaviour):
    """A plain leaf: the declared values as attributes; override ``update()``.

    Args:
        name: The behaviour's name.
        **declared: The declared params, context objects and ``ports``.
    """

    def __init__(self, name: str, **declared: Any) -> None:
        super().__init__(name=name)
        keep_declared(self, declared)


class Condition(Leaf):
    """A condition: SUCCESS when :meth:`check` holds, FAILURE otherwise, in the tick.

    Declare it with ``@leaf(condition=True)`` so palettes and exports say so.
    """

    def check(self) -> bool:
        """Whether the condition holds now (say why in ``feedback_message`` if useful)."""
        raise NotImplementedError(f"{type(self).__name__} must define check()")

    def update(self) -> Status:
        """Answer in the tick.

        Returns:
            SUCCESS or FAILURE.
        """
        return Status.SUCCESS if self.check() else Status.FAILURE


class StatefulLeaf(Leaf):
    """Long work on BehaviorTree.CPP's ``StatefulActionNode`` moments, without ROS."""

    def __init__(self, name: str, **declared: Any) -> None:
        super().__init__(name, **declared)
        self._started = False

    def on_start(self) -> Status:
        """Start the work (first tick of an activation); RUNNING to continue."""
        raise NotImplementedError(f"{type(self).__name__} must define on_start()")

    def on_running(self) -> Status:
        """Continue the work (each later tick while RUNNING)."""
        raise NotImplementedError(f"{type(self).__name__} must define on_running()")

    def on_halted(self) -> None:
        """Clean up: the leaf was stopped while RUNNING (a halt, not its own ending)."""

    def initialise(self) -> None:
        """Mark the start of an activation."""
        self._started = False

    def update(self) -> Status:
        """``on_start`` on the first tick of the activation, ``on_running`` after it.

        Returns:
            What the hook returned.
        """
        if not self._started:
            self._started = True
            return self.on_start()
        return self.on_running()

    def terminate(self, new_status: Status) -> None:
        """Call :meth:`on_halted` when stopped while RUNNING.

        Args:
            new_status: The status the leaf is moving to (INVALID on a halt).
        """
        if new_status == Status.INVALID and self.status == Status.RUNNING:
            self.on_halted()
