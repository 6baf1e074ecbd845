"""Dwell: RUNNING for a duration of the node's clock (ROS time), then SUCCESS.

With ``jitter`` the wait is longer by a random amount drawn at each start: a randomized
back-off, the way Ethernet's CSMA/CD breaks the symmetry of two stations that collided.
Two robots of a fleet that block each other in a doorway and back off with the same tree
would otherwise try again at the same instant, and meet again.
"""

from __future__ import annotations

import random
import time
from collections.abc import Callable
from typing import Any

import py_trees
from py_trees.common import Status

from sar_framework.engine.plugin import Param, leaf


@leaf(params=[Param("duration", float, default=1.0, minimum=0.0,
                    description="Seconds to wait, on the node's clock (simulated time with "
                                "use_sim_time)."),
              Param("jitter", float, default=0.0, minimum=0.0,
                    description="Up to this many seconds more, drawn uniformly at each start "
                                "(a randomized back-off).")])
class Dwell(py_trees.behaviour.Behaviour):
    """Dwell: RUNNING for ``duration`` seconds from its start, then SUCCESS.

    Time is the ROS node's clock given to ``setup(node=...)`` (so ``/clock`` time with
    ``use_sim_time``, the same at any simulation speed); without a node, wall time.

    Args:
        name: The behaviour's name.
        duration: Seconds.
        jitter: Up to this many seconds more, drawn anew at each start.
        rng: Where the jitter is drawn from (a fresh ``random.Random`` by default).
    """

    def __init__(self, name: str, *, duration: float, jitter: float,
                 rng: random.Random | None = None) -> None:
        super().__init__(name=name)
        self.duration = duration
        self.jitter = jitter
        self._rng = rng or random.Random()
        self._now: Callable[[], float] = time.monotonic
        self._until = 0.0
        self._wait = duration

    def setup(self, **kwargs: Any) -> None:
        """Follow the clock of ``kwargs["node"]`` when one is given."""
        node = kwargs.get("node")
        if node is not None:
            clock = node.get_clock()
            self._now = lambda: clock.now().nanoseconds / 1e9

    def initialise(self) -> None:
        """Start the wait (drawing its jitter)."""
        self._wait = self.duration + (self._rng.uniform(0.0, self.jitter) if self.jitter else 0.0)
        self._until = self._now() + self._wait

    def update(self) -> Status:
        """RUNNING until the duration has passed, then SUCCESS."""
        left = self._until - self._now()
        if left > 0:
            self.feedback_message = f"waiting: {left:.1f} s of {self._wait:.1f} s left"
            return Status.RUNNING
        self.feedback_message = f"waited {self._wait:.1f} s"
        return Status.SUCCESS
