"""BT.CPP 4's sequences and fallbacks: with memory, without, reactive.

- :class:`Sequence` resumes at the running child; a failure resets it to the first child.
- :class:`SequenceWithMemory` also resumes after a failure: the failed child is ticked
  again next time, the ones before it are not. After a child succeeds on its first tick
  it yields (returns RUNNING), as BT.CPP does when the tree can be woken up.
- :class:`ReactiveSequence` ticks from the first child every tick and halts the others
  when one is running.
- :class:`Fallback` and :class:`ReactiveFallback` mirror the two with SUCCESS and
  FAILURE swapped.
- :class:`AsyncSequence` and :class:`AsyncFallback` yield like SequenceWithMemory but
  restart after stopping, like Sequence and Fallback.

SKIPPED children are passed over; a composite whose children were all skipped is
SKIPPED itself.
"""

from __future__ import annotations

from collections.abc import Sequence as Children

from py_trees.common import Status

from sar_framework.engine.nodes.controls.base import (
    Behaviour,
    BtControl,
    Outcome,
    Steps,
    bt_status,
)


class _Stopping(BtControl):
    """A sequence (stopped by a failure) or a fallback (stopped by a success).

    Args:
        name: The behaviour's name.
        children: The children, in order.
    """

    #: The outcome that ends the run early (FAILURE for a sequence).
    stop_on: Outcome

    @property
    def otherwise(self) -> Outcome:
        """The outcome when every child is done (SUCCESS for a sequence)."""
        return Outcome.SUCCESS if self.stop_on is Outcome.FAILURE else Outcome.FAILURE


class _Ordered(_Stopping):
    """Sequence and Fallback: one child at a time, resuming at ``index``."""

    #: Whether a child that completes on its first tick yields (SequenceWithMemory).
    yields = False
    #: Whether stopping early resets to the first child (not SequenceWithMemory).
    restarts = True

    def __init__(self, name: str, children: Children[Behaviour]) -> None:
        super().__init__(name, children)
        self.index = 0
        self.skipped = 0

    def control(self) -> Steps:
        """Tick children from ``index`` until one runs or stops the run."""
        count = len(self.children)
        if self.was_idle:
            self.skipped = 0
        while self.index < count:
            child = self.children[self.index]
            was_idle = bt_status(child) == Status.INVALID
            result = yield from self.tick_child(child)
            if result is Outcome.RUNNING:
                return result
            if result is self.stop_on:
                if self.restarts:
                    self.reset_children()
                    self.index = 0
                else:
                    for index in range(self.index, count):
                        self.halt_child(index)
                return result
            self.index += 1
            if result is Outcome.SKIPPED:
                self.skipped += 1
            elif self.yields and was_idle and self.index < count:
                return Outcome.RUNNING
        all_skipped = self.skipped == count
        self.reset_children()
        self.index = 0
        self.skipped = 0
        return Outcome.SKIPPED if all_skipped else self.otherwise

    def halt(self) -> None:
        """Back to the first child (except SequenceWithMemory), children reset."""
        if self.restarts:
            self.index = 0
            self.skipped = 0
        super().halt()


class Sequence(_Ordered):
    """BT.CPP ``Sequence``: children in order until one fails; resumes at a running child."""

    stop_on = Outcome.FAILURE


class SequenceWithMemory(_Ordered):
    """BT.CPP ``SequenceWithMemory``: like Sequence, but a failed child is retried next tick."""

    stop_on = Outcome.FAILURE
    yields = True
    restarts = False


class AsyncSequence(_Ordered):
    """BT.CPP ``AsyncSequence``: a Sequence that yields after a child's first-tick success."""

    stop_on = Outcome.FAILURE
    yields = True


class AsyncFallback(_Ordered):
    """BT.CPP ``AsyncFallback``: a Fallback that yields after a child's first-tick failure."""

    stop_on = Outcome.SUCCESS
    yields = True


class Fallback(_Ordered):
    """BT.CPP ``Fallback``: children in order until one succeeds."""

    stop_on = Outcome.SUCCESS


class _Reactive(_Stopping):
    """ReactiveSequence and ReactiveFallback: from the first child, every tick."""

    def control(self) -> Steps:
        """Tick children from the first until one runs or stops the run."""
        all_skipped = True
        for index, child in enumerate(self.children):
            result = yield from self.tick_child(child)
            all_skipped = all_skipped and result is Outcome.SKIPPED
            if result is Outcome.RUNNING:
                for other in range(len(self.children)):
                    if other != index:
                        self.halt_child(other)
                return result
            if result is self.stop_on:
                self.reset_children()
                return result
            if result is Outcome.SKIPPED:
                self.halt_child(index)  # so that it can be skipped again
        self.reset_children()
        return Outcome.SKIPPED if all_skipped else self.otherwise


class ReactiveSequence(_Reactive):
    """BT.CPP ``ReactiveSequence``: every tick from the first child; a failure stops it."""

    stop_on = Outcome.FAILURE


class ReactiveFallback(_Reactive):
    """BT.CPP ``ReactiveFallback``: every tick from the first child; a success stops it."""

    stop_on = Outcome.SUCCESS
