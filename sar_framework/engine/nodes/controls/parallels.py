"""BT.CPP 4's parallels: thresholds (:class:`Parallel`) and wait-for-all (:class:`ParallelAll`).

Both tick every child that has not completed yet, in order, on every tick; a completed
child is not ticked again until the parallel finishes or is halted. A threshold below
zero counts from the number of children: ``-1`` is all of them, ``-2`` all but one.
"""

from __future__ import annotations

from collections.abc import Sequence as Children

from sar_framework.engine.nodes.controls.base import Behaviour, BtControl, Outcome, Steps


def threshold(value: int, children: int) -> int:
    """A BT.CPP threshold: ``value`` itself, or counted from ``children`` when negative."""
    return max(children + value + 1, 0) if value < 0 else value


class _Thresholds(BtControl):
    """A parallel with thresholds checked against its number of children."""

    def check_threshold(self, port: str, value: int, error: type[Exception]) -> None:
        """Raise ``error`` when the threshold ``value`` of ``port`` can never be reached."""
        count = len(self.children)
        if threshold(value, count) > count:
            raise error(f"{self.name}: '{port}' {value} is more than the {count} children "
                        "(BT.CPP: the threshold can never be reached)")

    def read_port(self, port: str, value: int) -> None:
        """Take a threshold read from its entry (BT.CPP throws when it is out of reach)."""
        self.check_threshold(port, value, RuntimeError)
        setattr(self, port, value)


class Parallel(_Thresholds):
    """BT.CPP ``Parallel``: SUCCESS at ``success_count`` successes, FAILURE at ``failure_count``.

    The thresholds are checked after each child's tick, so the children after the one
    that reached a threshold are not ticked that tick. It also fails as soon as too
    few children are left to reach ``success_count``. With a negative
    ``success_count``, skipped children count as successes.

    Args:
        name: The behaviour's name.
        children: The children, in order.
        success_count: Successes needed (negative: counted from the number of children).
        failure_count: Failures that fail the parallel (negative: likewise).

    Raises:
        ValueError: A threshold is above the number of children.
    """

    def __init__(self, name: str, children: Children[Behaviour], success_count: int = -1,
                 failure_count: int = 1) -> None:
        super().__init__(name, children)
        self.success_count = success_count
        self.failure_count = failure_count
        self.check_threshold("success_count", success_count, ValueError)
        self.check_threshold("failure_count", failure_count, ValueError)
        self.completed: set[int] = set()
        self.successes = 0
        self.failures = 0

    def control(self) -> Steps:
        """Tick the children not completed yet, checking the thresholds after each."""
        count = len(self.children)
        needed = threshold(self.success_count, count)
        fails_at = threshold(self.failure_count, count)
        skipped = 0
        for index, child in enumerate(self.children):
            if index not in self.completed:
                result = yield from self.tick_child(child)
                if result is Outcome.SKIPPED:
                    skipped += 1
                elif result is Outcome.SUCCESS:
                    self.completed.add(index)
                    self.successes += 1
                elif result is Outcome.FAILURE:
                    self.completed.add(index)
                    self.failures += 1
            if self.successes >= needed or (
                self.success_count < 0 and self.successes + skipped >= needed
            ):
                self.clear()
                self.reset_children()
                return Outcome.SUCCESS
            if count - self.failures < needed or self.failures == fails_at:
                self.clear()
                self.reset_children()
                return Outcome.FAILURE
        return Outcome.SKIPPED if skipped == count else Outcome.RUNNING

    def clear(self) -> None:
        """Forget the completed children and the counts."""
        self.completed.clear()
        self.successes = 0
        self.failures = 0

    def halt(self) -> None:
        """Forget the counts; halt and reset the children."""
        self.clear()
        super().halt()


class ParallelAll(_Thresholds):
    """BT.CPP ``ParallelAll``: wait for every child; FAILURE when ``max_failures`` failed.

    Args:
        name: The behaviour's name.
        children: The children, in order.
        max_failures: Failures that make the result FAILURE (negative: counted from the
            number of children).

    Raises:
        ValueError: ``max_failures`` is above the number of children.
    """

    def __init__(self, name: str, children: Children[Behaviour], max_failures: int = 1) -> None:
        super().__init__(name, children)
        self.max_failures = max_failures
        self.check_threshold("max_failures", max_failures, ValueError)
        self.completed: set[int] = set()
        self.failures = 0

    def control(self) -> Steps:
        """Tick the children not completed yet; decide once all are done."""
        count = len(self.children)
        fails_at = threshold(self.max_failures, count)
        skipped = 0
        for index, child in enumerate(self.children):
            if index in self.completed:
                continue
            result = yield from self.tick_child(child)
            if result is Outcome.SUCCESS:
                self.completed.add(index)
            elif result is Outcome.FAILURE:
                self.completed.add(index)
                self.failures += 1
            elif result is Outcome.SKIPPED:
                skipped += 1
        if skipped == count:
            return Outcome.SKIPPED
        if skipped + len(self.completed) >= count:
            self.reset_children()
            self.completed.clear()
            failed = self.failures >= fails_at
            self.failures = 0
            return Outcome.FAILURE if failed else Outcome.SUCCESS
        return Outcome.RUNNING

    def halt(self) -> None:
        """Forget the counts; halt and reset the children."""
        self.completed.clear()
        self.failures = 0
        super().halt()
