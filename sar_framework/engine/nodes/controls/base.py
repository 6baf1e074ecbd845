"""What every BT.CPP-style control and decorator shares: outcomes, halting, status.

BehaviorTree.CPP and py_trees disagree on three things these base classes reconcile:

- **SKIPPED.** A child's :class:`Outcome` is read from its py_trees status plus the
  SKIPPED mark of :mod:`sar_framework.engine.nodes.skipping`; a node of ours that returns
  SKIPPED sets ``Status.SUCCESS`` and the mark.
- **Status as BT.CPP sees it, IDLE included.** BT.CPP resets a finished child to IDLE;
  py_trees keeps the status it returned (``tip()``, snapshots and every view read it).
  So BT.CPP's status lives apart, in the attribute named by :data:`BT_STATUS`
  (``bt_status``; ``Status.INVALID`` stands for IDLE), read with :func:`bt_status` and
  set to IDLE with :func:`reset_status`. Each node of ours keeps it itself: a tick sets
  it to RUNNING first and then to the result, except that a SKIPPED result leaves it
  unchanged, as BT.CPP's ``executeTick`` does (a few BT.CPP nodes never set RUNNING
  first: ``marks_running``). Any other child (a leaf, a py_trees node) gets it from
  :func:`tick_child`: the status its tick returned. A node whose py_trees status is
  INVALID (never ticked, or halted) is IDLE. ``isStatusActive`` and "halt only a RUNNING
  child" read it; only ``stop(Status.INVALID)`` makes a py_trees status INVALID.
- **Halting.** :func:`halt_child` is BT.CPP's ``haltChild``: a running child is halted
  (py_trees ``stop(Status.INVALID)``), any other child only becomes IDLE (its
  ``bt_status``; no ``terminate`` call, no recursion, its py_trees status kept). A node
  of ours stopped with ``INVALID`` while running runs its own :meth:`BtControl.halt`
  (BT.CPP's ``halt()``); stopped while not running it only becomes IDLE. A root that
  completes becomes IDLE too, as BT.CPP's ``Tree::tickRoot`` resets it.

Subclasses write one generator, ``control()`` (composites) or ``decorate()``
(decorators), that ticks children with ``yield from self.tick_child(child)`` and returns
an :class:`Outcome`.
"""

from __future__ import annotations

from collections.abc import Callable, Generator, Iterator, Sequence
from enum import Enum

import py_trees
from py_trees.common import Status

from sar_framework.engine.nodes.controls.read_ports import ReadsPorts
from sar_framework.engine.nodes.skipping import mark_skipped, was_skipped

Behaviour = py_trees.behaviour.Behaviour
#: A clock: returns the current time in seconds.
Clock = Callable[[], float]
#: The generator a control or decorator writes: yields ticked behaviours, returns an outcome.
Steps = Generator[Behaviour, None, "Outcome"]
#: The attribute holding the status BT.CPP would show (``Status.INVALID``: IDLE), apart
#: from py_trees' ``status``; on our nodes and on every child they tick.
BT_STATUS = "bt_status"


class Outcome(Enum):
    """A tick's result as BT.CPP reports it (py_trees' three plus SKIPPED)."""

    SUCCESS = "SUCCESS"
    FAILURE = "FAILURE"
    RUNNING = "RUNNING"
    SKIPPED = "SKIPPED"

    @property
    def completed(self) -> bool:
        """BT.CPP's ``isStatusCompleted``: SUCCESS or FAILURE."""
        return self is Outcome.SUCCESS or self is Outcome.FAILURE


_TO_STATUS = {
    Outcome.SUCCESS: Status.SUCCESS,
    Outcome.FAILURE: Status.FAILURE,
    Outcome.RUNNING: Status.RUNNING,
    Outcome.SKIPPED: Status.SUCCESS,
}


def outcome(child: Behaviour) -> Outcome:
    """Return the outcome of ``child``'s latest tick.

    Raises:
        RuntimeError: The child is INVALID after a tick (BT.CPP: "should not return IDLE").
    """
    status = child.status
    if status == Status.SUCCESS:
        return Outcome.SKIPPED if was_skipped(child) else Outcome.SUCCESS
    if status == Status.INVALID:
        raise RuntimeError(f"'{child.name}' returned INVALID (IDLE) from a tick")
    return Outcome(status.name)


def bt_status(node: Behaviour) -> Status:
    """The status BT.CPP would show for ``node`` (INVALID is IDLE).

    A node that py_trees shows INVALID (never ticked, or halted) is IDLE; otherwise its
    ``bt_status`` says, or, when it has none yet, its py_trees status.
    """
    if node.status == Status.INVALID:
        return Status.INVALID
    return getattr(node, BT_STATUS, node.status)


def reset_status(node: Behaviour) -> None:
    """BT.CPP's ``resetStatus``: IDLE, without halting and without touching children.

    Only ``bt_status`` changes: py_trees' ``status`` keeps what the node returned.
    """
    setattr(node, BT_STATUS, Status.INVALID)


def halt_child(child: Behaviour) -> None:
    """BT.CPP's ``haltChild``: halt ``child`` when it runs, then reset it to IDLE."""
    if Status.RUNNING in (bt_status(child), child.status):
        child.stop(Status.INVALID)
    reset_status(child)


def tick_child(child: Behaviour) -> Steps:
    """Tick ``child`` once (yielding what it ticks); return its outcome.

    A child that is not a node of ours (which keep ``bt_status`` themselves) gets the
    status it returned as its ``bt_status``.
    """
    yield from child.tick()
    if not isinstance(child, _BtNode):
        setattr(child, BT_STATUS, child.status)
    return outcome(child)


class _BtNode(ReadsPorts):
    """The tick and stop both of our base classes share (mixed into a py_trees class)."""

    bt_status: Status
    was_idle: bool
    #: Whether the BT.CPP node sets RUNNING before its tick's work (most do; it shows
    #: when the tick returns SKIPPED, which leaves BT.CPP's status as it was).
    marks_running = True
    children: list[Behaviour]
    status: Status
    name: str

    def steps(self) -> Steps:
        """The node's own tick: yields ticked children, returns an outcome."""
        raise NotImplementedError

    def halt(self) -> None:
        """BT.CPP's ``halt()``: reset every child (subclasses also reset their state)."""
        self.reset_children()

    def reset_children(self) -> None:
        """BT.CPP's ``resetChildren``: halt running children, reset all to IDLE."""
        for child in self.children:
            halt_child(child)

    def tick(self) -> Iterator[Behaviour]:
        """Tick the node the BT.CPP way (see the module docstring)."""
        self.read_ports()
        self.was_idle = self.bt_status == Status.INVALID  # not isStatusActive()
        if self.marks_running:
            self.bt_status = Status.RUNNING
        result = yield from self.steps()
        self.finish(result)
        yield self  # type: ignore[misc]

    def finish(self, result: Outcome) -> None:
        """Record ``result`` as py_trees and BT.CPP statuses and the SKIPPED mark."""
        status = _TO_STATUS[result]
        mark_skipped(self, result is Outcome.SKIPPED)
        if result is not Outcome.SKIPPED:
            self.bt_status = status
        if self.parent is None and result.completed:  # type: ignore[attr-defined]
            self.bt_status = Status.INVALID  # BT.CPP's tickRoot resets a finished root
        if status != Status.RUNNING:
            self.terminate(status)  # type: ignore[attr-defined]
        self.status = status

    def stop(self, new_status: Status = Status.INVALID) -> None:
        """Stop the node; with INVALID: BT.CPP's ``haltNode`` if running, else reset."""
        if new_status == Status.INVALID:
            if Status.RUNNING in (self.bt_status, self.status):
                self.halt()
            self.bt_status = Status.INVALID
            mark_skipped(self, False)
        self.terminate(new_status)  # type: ignore[attr-defined]
        self.status = new_status
        self.iterator = self.tick()


class BtControl(_BtNode, py_trees.composites.Composite):
    """A composite ticked by :meth:`control`, with BT.CPP's halting rules.

    Args:
        name: The behaviour's name.
        children: The children, in order.
    """

    def __init__(self, name: str, children: Sequence[Behaviour]) -> None:
        super().__init__(name, list(children))
        self.bt_status = Status.INVALID
        self.was_idle = True

    def steps(self) -> Steps:
        """Run :meth:`control`, keeping ``current_child`` for py_trees' introspection."""
        return self.control()

    def control(self) -> Steps:
        """Tick children as the node's BT.CPP counterpart does; return the outcome."""
        raise NotImplementedError

    def tick_child(self, child: Behaviour) -> Steps:
        """Tick ``child``; return its outcome."""
        self.current_child = child
        return (yield from tick_child(child))

    def halt_child(self, index: int) -> None:
        """Halt (if running) and reset the child at ``index``."""
        halt_child(self.children[index])
        self.forget_halted()

    def reset_children(self) -> None:
        """BT.CPP's ``resetChildren``: halt running children, reset all to IDLE."""
        super().reset_children()
        self.forget_halted()

    def forget_halted(self) -> None:
        """A current child just halted is current no more, as py_trees' ``stop`` has it.

        Its py_trees status is INVALID, so ``tip()`` stops at this node instead of
        returning None through it.
        """
        if self.current_child is not None and self.current_child.status == Status.INVALID:
            self.current_child = None

    def halt(self) -> None:
        """Reset every child (BT.CPP ``ControlNode::halt``); subclasses reset their state."""
        self.current_child = None
        self.reset_children()


class BtDecorator(_BtNode, py_trees.decorators.Decorator):
    """A decorator ticked by :meth:`decorate`, with BT.CPP's halting rules.

    Like BT.CPP's ``DecoratorNode::executeTick``, a child that completed (SUCCESS or
    FAILURE) is reset to IDLE after every tick of the decorator.

    Args:
        name: The behaviour's name.
        child: The decorated behaviour.
    """

    def __init__(self, name: str, child: Behaviour) -> None:
        super().__init__(name=name, child=child)
        self.bt_status = Status.INVALID
        self.was_idle = True

    def steps(self) -> Steps:
        """Run :meth:`decorate`, then reset a child that completed."""
        result = yield from self.decorate()
        if bt_status(self.decorated) in (Status.SUCCESS, Status.FAILURE):
            reset_status(self.decorated)
        return result

    def decorate(self) -> Steps:
        """Tick the child as the node's BT.CPP counterpart does; return the outcome."""
        raise NotImplementedError

    def update(self) -> Status:
        """Unused (:meth:`decorate` decides); py_trees' Decorator declares it abstract."""
        return self.status

    def tick_child(self) -> Steps:
        """Tick the decorated child; return its outcome."""
        return (yield from tick_child(self.decorated))

    def reset_child(self) -> None:
        """BT.CPP's ``resetChild`` / ``haltChild``: halt if running, reset to IDLE."""
        halt_child(self.decorated)
