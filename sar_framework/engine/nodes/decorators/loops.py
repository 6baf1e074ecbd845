"""BT.CPP 4's looping decorators: Repeat, RetryUntilSuccessful, and RunOnce.

:class:`Repeat` and :class:`RetryUntilSuccessful` re-tick their child within one tick
when it completed after running, and yield (return RUNNING) between attempts when it
completed on its first tick, as BT.CPP does in a tree that can be woken up. ``-1``
loops forever. :class:`RunOnce` ticks its child until it completes once, then returns
SKIPPED (``then_skip``) or that same result forever after.
"""

from __future__ import annotations

from py_trees.common import Status

from sar_framework.engine.nodes.controls.base import (
    Behaviour,
    BtDecorator,
    Outcome,
    Steps,
    bt_status,
)


class _Loop(BtDecorator):
    """Re-tick the child while it gives ``again`` (up to ``limit`` times; -1: forever)."""

    #: The child's result that is tried again; the loop's result once the limit is reached.
    again: Outcome

    def __init__(self, name: str, child: Behaviour, limit: int) -> None:
        super().__init__(name, child)
        self.limit = limit
        self.count = 0

    def looping(self) -> bool:
        """Whether another attempt is allowed."""
        return self.count < self.limit or self.limit == -1

    def read_port(self, port: str, value: int) -> None:
        """Take the limit read from its entry."""
        self.limit = value

    def decorate(self) -> Steps:
        """Tick the child, again within this tick while it completes after running."""
        while self.looping():
            was_idle = bt_status(self.decorated) == Status.INVALID
            result = yield from self.tick_child()
            if result is Outcome.RUNNING:
                return result
            if result is Outcome.SKIPPED:
                self.reset_child()
                return result
            if result is not self.again:
                self.count = 0
                self.reset_child()
                return result
            self.count += 1
            self.reset_child()
            if was_idle and self.looping():
                return Outcome.RUNNING
        self.count = 0
        return self.again

    def halt(self) -> None:
        """Forget the attempts made; the child halted and reset."""
        self.count = 0
        super().halt()


class Repeat(_Loop):
    """BT.CPP ``Repeat``: tick a succeeding child ``num_cycles`` times; a failure fails.

    Args:
        name: The behaviour's name.
        child: The decorated behaviour.
        num_cycles: Successes needed (-1: repeat forever).
    """

    again = Outcome.SUCCESS

    def __init__(self, name: str, child: Behaviour, num_cycles: int) -> None:
        super().__init__(name, child, num_cycles)


class RetryUntilSuccessful(_Loop):
    """BT.CPP ``RetryUntilSuccessful``: re-tick a failing child up to ``num_attempts`` times.

    Args:
        name: The behaviour's name.
        child: The decorated behaviour.
        num_attempts: Attempts allowed (-1: retry forever).
    """

    again = Outcome.FAILURE

    def __init__(self, name: str, child: Behaviour, num_attempts: int) -> None:
        super().__init__(name, child, num_attempts)


class RunOnce(BtDecorator):
    """BT.CPP ``RunOnce``: run the child to completion once; then skip or repeat the result.

    The latch survives halts (BT.CPP resets it only when the tree is rebuilt).

    Args:
        name: The behaviour's name.
        child: The decorated behaviour.
        then_skip: After the first completion, return SKIPPED (true) or the child's
            result of that completion (false).
    """

    def __init__(self, name: str, child: Behaviour, then_skip: bool = True) -> None:
        super().__init__(name, child)
        self.then_skip = then_skip
        self.returned: Outcome | None = None

    marks_running = False

    def read_port(self, port: str, value: bool) -> None:
        """Take ``then_skip`` read from its entry."""
        self.then_skip = value

    def decorate(self) -> Steps:
        """Tick the child until it completes once; afterwards do not tick it."""
        if self.returned is not None:
            return Outcome.SKIPPED if self.then_skip else self.returned
        self.bt_status = Status.RUNNING
        result = yield from self.tick_child()
        if result.completed:
            self.returned = result
            self.reset_child()
        return result
