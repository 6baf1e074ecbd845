"""BT.CPP 4's clock-driven decorators: Delay and Timeout, on a given clock.

BT.CPP runs a timer thread; here the clock is read when the node is ticked, so the
behaviour is the same at each tick and can be driven by a simulated clock (the build
context's ``clock``, see :mod:`sar_framework.engine.building.control_build`; default
``time.monotonic``).
"""

from __future__ import annotations

import time

from py_trees.common import Status

from sar_framework.engine.nodes.controls.base import (
    Behaviour,
    BtDecorator,
    Clock,
    Outcome,
    Steps,
    bt_status,
)


class _Timed(BtDecorator):
    """A decorator that times ``duration`` seconds from its start, on ``clock``."""

    def __init__(self, name: str, child: Behaviour, msec: int, clock: Clock) -> None:
        super().__init__(name, child)
        self.duration = msec / 1000.0
        self.clock = clock
        self.started_at: float | None = None

    def read_port(self, port: str, value: int) -> None:
        """Take the milliseconds read from their entry."""
        self.duration = value / 1000.0

    def tick_until_completed(self) -> Steps:
        """Tick the child; once it completed, reset it and the start."""
        result = yield from self.tick_child()
        if result.completed:
            self.started_at = None
            self.reset_child()
        return result

    def halt(self) -> None:
        """Forget the start; the child halted and reset."""
        self.started_at = None
        super().halt()


class Delay(_Timed):
    """BT.CPP ``Delay``: RUNNING for ``delay_msec``, then tick the child until it completes.

    Args:
        name: The behaviour's name.
        child: The decorated behaviour.
        delay_msec: Milliseconds to wait before the child's first tick.
        clock: Returns the time in seconds.
    """

    def __init__(self, name: str, child: Behaviour, delay_msec: int,
                 clock: Clock = time.monotonic) -> None:
        super().__init__(name, child, delay_msec, clock)

    def decorate(self) -> Steps:
        """Start the delay; once it passed, tick the child."""
        if self.started_at is None:
            self.started_at = self.clock()
        if self.clock() - self.started_at < self.duration:
            return Outcome.RUNNING
        return (yield from self.tick_until_completed())


class Timeout(_Timed):
    """BT.CPP ``Timeout``: halt the child and fail when it still runs after ``msec``.

    ``msec`` 0 never times out (BT.CPP starts no timer).

    Args:
        name: The behaviour's name.
        child: The decorated behaviour.
        msec: Milliseconds the child may run.
        clock: Returns the time in seconds.
    """

    def __init__(self, name: str, child: Behaviour, msec: int,
                 clock: Clock = time.monotonic) -> None:
        super().__init__(name, child, msec, clock)
        self.deadline: float | None = None

    def decorate(self) -> Steps:
        """Start the bound; fail without ticking the child once it passed while running."""
        if self.started_at is None:
            self.started_at = self.clock()
            self.deadline = self.started_at + self.duration if self.duration > 0 else None
        if (self.deadline is not None and self.clock() >= self.deadline
                and bt_status(self.decorated) == Status.RUNNING):
            self.reset_child()
            self.started_at = None
            return Outcome.FAILURE
        return (yield from self.tick_until_completed())
