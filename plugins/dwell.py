"""Dwell: RUNNING for a duration of the node's clock (ROS time), then SUCCESS."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import py_trees
from py_trees.common import Status

from sar_framework.engine.plugin import Param, leaf


@leaf(params=[Param("duration", float, default=1.0, minimum=0.0,
                    description="Seconds to wait, on the node's clock (simulated time with "
                                "use_sim_time).")])
class Dwell(py_trees.behaviour.Behaviour):
    """Dwell: RUNNING for ``duration`` seconds from its start, then SUCCESS.

    Time is the ROS node's clock given to ``setup(node=...)`` (so ``/clock`` time with
    ``use_sim_time``, the same at any simulation speed); without a node, wall time.

    Args:
        name: The behaviour's name.
        duration: Seconds.
    """

    def __init__(self, name: str, *, duration: float) -> None:
        super().__init__(name=name)
        self.duration = duration
        self._now: Callable[[], float] = time.monotonic
        self._until = 0.0

    def setup(self, **kwargs: Any) -> None:
        """Follow the clock of ``kwargs["node"]`` when one is given."""
        node = kwargs.get("node")
        if node is not None:
            clock = node.get_clock()
            self._now = lambda: clock.now().nanoseconds / 1e9

    def initialise(self) -> None:
        """Start the wait."""
        self._until = self._now() + self.duration

    def update(self) -> Status:
        """RUNNING until the duration has passed, then SUCCESS."""
        left = self._until - self._now()
        if left > 0:
            self.feedback_message = f"waiting: {left:.1f} s of {self.duration:g} s left"
            return Status.RUNNING
        self.feedback_message = f"waited {self.duration:g} s"
        return Status.SUCCESS
