"""A ``timeout`` decorator that reads an injected clock (e.g. the ROS node's) (no ROS here).

py_trees' ``Timeout`` counts wall seconds (``time.monotonic``). A runner that ticks on ROS
time passes ``context={CLOCK_KEY: now}`` to ``load_tree``, where ``now()`` returns the
node's clock in seconds (``/clock`` time with ``use_sim_time``); every ``timeout`` of the
tree is then built as :class:`ClockTimeout` on that clock, so a tree behaves the same at any
simulation speed. Without it, ``timeout`` is py_trees' own.
"""

from __future__ import annotations

from collections.abc import Callable

import py_trees
from py_trees.common import Status

CLOCK_KEY = "clock"
"""The build-context key of the clock (a callable returning seconds)."""


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
