"""Nav2's ROS-free decorators (``nav2_behavior_tree``, Jazzy): RateController, SingleTrigger.

Both restart when their status was reset to IDLE by their parent (BT.CPP's
``isStatusActive``), which is how Nav2 trees re-arm them between runs.
"""

from __future__ import annotations

import time

from py_trees.common import Status

from sar_framework.engine.controls.base import (
    Behaviour,
    BtDecorator,
    Clock,
    Outcome,
    Steps,
    bt_status,
)


class RateController(BtDecorator):
    """Nav2 ``RateController``: tick the child at most ``hz`` times a second.

    Between permitted ticks it returns RUNNING without ticking the child; a running
    child is ticked every time; a success restarts the period.

    Args:
        name: The behaviour's name.
        child: The decorated behaviour.
        hz: Ticks per second the child gets.
        clock: Returns the time in seconds.
    """

    def __init__(self, name: str, child: Behaviour, hz: float = 10.0,
                 clock: Clock = time.monotonic) -> None:
        if hz <= 0:
            raise ValueError(f"RateController '{name}': hz must be > 0, got {hz}")
        super().__init__(name, child)
        self.hz = hz
        self.clock = clock
        self.period = 1.0 / hz
        self.start = 0.0
        self.first = False

    def decorate(self) -> Steps:
        """Tick the child on the first tick, while it runs, or once the period passed."""
        if self.was_idle:
            self.period = 1.0 / self.hz
            self.start = self.clock()
            self.first = True
        if (self.first or bt_status(self.decorated) == Status.RUNNING
                or self.clock() - self.start >= self.period):
            self.first = False
            result = yield from self.tick_child()
            if result is Outcome.SUCCESS:
                self.start = self.clock()
            return result
        return Outcome.RUNNING


class SingleTrigger(BtDecorator):
    """Nav2 ``SingleTrigger``: tick the child to one completion, then FAILURE until reset.

    Args:
        name: The behaviour's name.
        child: The decorated behaviour.
    """

    def __init__(self, name: str, child: Behaviour) -> None:
        super().__init__(name, child)
        self.first = True

    def decorate(self) -> Steps:
        """The child's result until it completed once in this activation, then FAILURE."""
        if self.was_idle:
            self.first = True
        if not self.first:
            return Outcome.FAILURE
        result = yield from self.tick_child()
        if result.completed:
            self.first = False
        return result
