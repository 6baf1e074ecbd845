"""Behaviours built on BehaviorTree.CPP 4 scripts.

``Script``, ``ScriptCondition``, ``Precondition`` and the pre/post-condition attributes
every BT.CPP node takes.

Each takes compiled scripts (:func:`~sar_framework.engine.scripting.compile_script`) and
the :class:`~sar_framework.engine.variables.Variables` they read and write:

* :class:`Script` runs its code and succeeds.
* :class:`ScriptCondition` succeeds when its code's value is true, fails otherwise.
* :class:`Precondition` (a decorator) ticks its child when ``if`` holds and otherwise
  returns its ``else`` status without ticking it; once the child is RUNNING the
  condition is not evaluated again until the child finishes.
* :class:`PrePostConditions` (a decorator around one node) implements ``_failureIf
  _successIf _skipIf _while`` (checked in that order before a node starts; only
  ``_while`` is checked again while it runs, and halts it when false) and ``_onSuccess
  _onFailure _post`` (run when it finishes) and ``_onHalted`` (run when it is halted
  while RUNNING), as BT.CPP's ``TreeNode::executeTick``/``haltNode`` do.

SKIPPED follows :mod:`~sar_framework.engine.nodes.skipping`: SUCCESS plus the skipped mark.
A script that fails at run time raises :class:`~sar_framework.engine.scripting.ScriptError`
out of the tick, as BT.CPP throws.
"""

from __future__ import annotations

import enum
from collections.abc import Iterator

import py_trees
from py_trees.behaviour import Behaviour
from py_trees.common import Status

from ..scripting import CompiledScript, as_condition
from ..variables import Variables
from .skipping import mark_skipped, was_skipped

#: BT.CPP's attribute -> the keyword of :class:`PrePostConditions` that takes its script.
ATTRIBUTES = {
    "_failureIf": "failure_if", "_successIf": "success_if", "_skipIf": "skip_if",
    "_while": "while_", "_onSuccess": "on_success", "_onFailure": "on_failure",
    "_onHalted": "on_halted", "_post": "post",
}


class ElseStatus(enum.Enum):
    """What :class:`Precondition` returns when ``if`` is false (BT.CPP's ``else`` port)."""

    SUCCESS = "SUCCESS"
    FAILURE = "FAILURE"
    RUNNING = "RUNNING"
    SKIPPED = "SKIPPED"

    @property
    def status(self) -> Status:
        """The py_trees status it is returned as (SKIPPED is SUCCESS plus the mark)."""
        return Status.SUCCESS if self is ElseStatus.SKIPPED else Status[self.value]


def holds(script: CompiledScript, variables: Variables) -> bool:
    """Run a condition script and judge its value as BT.CPP casts it to bool."""
    return as_condition(script, script.run(variables))


class _ScriptLeaf(Behaviour):
    """A leaf that runs one script on its variables."""

    def __init__(self, name: str, script: CompiledScript, variables: Variables) -> None:
        super().__init__(name=name)
        self.script = script
        self.variables = variables


class Script(_ScriptLeaf):
    """Run a script and succeed (BT.CPP's ``Script``; its value is not used).

    Args:
        name: The behaviour's name.
        script: The code.
        variables: What it reads and writes.
    """

    def update(self) -> Status:
        """Run the code; SUCCESS."""
        self.script.run(self.variables)
        self.feedback_message = "ran"
        mark_skipped(self, False)
        return Status.SUCCESS


class ScriptCondition(_ScriptLeaf):
    """SUCCESS when the script's value is true, else FAILURE (BT.CPP's ``ScriptCondition``).

    Args:
        name: The behaviour's name.
        script: The code; its last expression is the condition.
        variables: What it reads and writes.
    """

    def update(self) -> Status:
        """Run the code and judge its value."""
        result = holds(self.script, self.variables)
        self.feedback_message = "true" if result else "false"
        mark_skipped(self, False)
        return Status.SUCCESS if result else Status.FAILURE


class _ScriptedDecorator(py_trees.decorators.Decorator):
    """A decorator that decides itself whether to tick its child this time."""

    def update(self) -> Status:
        """Not used: :meth:`tick` decides the status itself."""
        return self.decorated.status

    def finish(self, status: Status, skipped: bool = False) -> None:
        """End this tick with ``status`` (SUCCESS stands for SKIPPED when ``skipped``)."""
        if status != Status.RUNNING:
            self.stop(status)
        self.status = status
        mark_skipped(self, skipped)

    def tick_child(self) -> Iterator[Behaviour]:
        """Tick the child; afterwards ``self.decorated.status`` holds its result."""
        yield from self.decorated.tick()

    def child_outcome(self) -> tuple[Status, bool]:
        """The child's latest status, and whether it stands for SKIPPED."""
        status = self.decorated.status
        return status, status == Status.SUCCESS and was_skipped(self.decorated)


class Precondition(_ScriptedDecorator):
    """Tick the child only when a condition holds (BT.CPP's ``Precondition``).

    The condition is evaluated when the child is not running; while the child is
    RUNNING it is ticked without evaluating it again. When the condition is false the
    decorator returns ``else_status`` and does not tick the child.

    Args:
        name: The behaviour's name.
        child: The decorated behaviour.
        condition: BT.CPP's ``if`` port.
        variables: What the condition reads (and writes, if it assigns).
        else_status: BT.CPP's ``else`` port (FAILURE by default).
    """

    def __init__(self, name: str, child: Behaviour, condition: CompiledScript,
                 variables: Variables, else_status: ElseStatus = ElseStatus.FAILURE) -> None:
        super().__init__(name=name, child=child)
        self.condition = condition
        self.variables = variables
        self.else_status = else_status
        self.child_running = False

    def tick(self) -> Iterator[Behaviour]:
        """Evaluate the condition unless the child is running, then tick it or not."""
        if self.status != Status.RUNNING:
            self.initialise()
        if not self.child_running:
            if not holds(self.condition, self.variables):
                self.feedback_message = f"'if' is false: {self.else_status.value}"
                self.finish(self.else_status.status, self.else_status is ElseStatus.SKIPPED)
                yield self
                return
            self.child_running = True
        yield from self.tick_child()
        status, skipped = self.child_outcome()
        self.child_running = status == Status.RUNNING
        self.feedback_message = "child skipped" if skipped else f"child {status.value}"
        self.finish(status, skipped)
        yield self

    def stop(self, new_status: Status) -> None:
        """Stop (a halt also forgets that the child had started)."""
        if new_status == Status.INVALID:
            self.child_running = False
        super().stop(new_status)


class PrePostConditions(_ScriptedDecorator):
    """One node with BT.CPP's pre- and post-condition attributes (each script optional).

    Before the node starts (it is not RUNNING), in this order: ``failure_if`` true ->
    FAILURE, ``success_if`` true -> SUCCESS, ``skip_if`` true -> SKIPPED, ``while_`` false
    -> SKIPPED, each without ticking the node. While it is RUNNING only ``while_`` is
    evaluated: false halts the node, runs ``on_halted`` and returns SKIPPED. When the
    result (the node's, or a pre-condition's) is SUCCESS, ``on_success`` runs; when
    FAILURE, ``on_failure``; then ``post`` in both cases (not after SKIPPED or a halt).
    Halting it from outside while RUNNING halts the node and runs ``on_halted``.

    Args:
        name: The behaviour's name.
        child: The node the attributes belong to.
        variables: What the scripts read and write.
        failure_if: ``_failureIf``.
        success_if: ``_successIf``.
        skip_if: ``_skipIf``.
        while_: ``_while``.
        on_success: ``_onSuccess``.
        on_failure: ``_onFailure``.
        on_halted: ``_onHalted``.
        post: ``_post``.
    """

    def __init__(self, name: str, child: Behaviour, variables: Variables, *,
                 failure_if: CompiledScript | None = None,
                 success_if: CompiledScript | None = None,
                 skip_if: CompiledScript | None = None,
                 while_: CompiledScript | None = None,
                 on_success: CompiledScript | None = None,
                 on_failure: CompiledScript | None = None,
                 on_halted: CompiledScript | None = None,
                 post: CompiledScript | None = None) -> None:
        super().__init__(name=name, child=child)
        self.variables = variables
        self.failure_if, self.success_if, self.skip_if = failure_if, success_if, skip_if
        self.while_ = while_
        self.on_success, self.on_failure, self.on_halted = on_success, on_failure, on_halted
        self.post = post

    def tick(self) -> Iterator[Behaviour]:
        """Check the pre-conditions, tick the node if they let it, run the post-conditions."""
        if self.status != Status.RUNNING:
            self.initialise()
        outcome = self.pre_conditions()
        if outcome is None:
            yield from self.tick_child()
            outcome = self.child_outcome()
            self.feedback_message = "skipped" if outcome[1] else outcome[0].value
        status, skipped = outcome
        if status in (Status.SUCCESS, Status.FAILURE) and not skipped:
            self.run(self.on_success if status == Status.SUCCESS else self.on_failure)
            self.run(self.post)
        self.finish(status, skipped)
        yield self

    def pre_conditions(self) -> tuple[Status, bool] | None:
        """The status the pre-conditions give (and whether it is SKIPPED), or None to tick."""
        if self.status != Status.RUNNING:
            checks = ((self.failure_if, True, Status.FAILURE, False, "_failureIf is true"),
                      (self.success_if, True, Status.SUCCESS, False, "_successIf is true"),
                      (self.skip_if, True, Status.SUCCESS, True, "_skipIf is true"),
                      (self.while_, False, Status.SUCCESS, True, "_while is false"))
            for script, when, status, skipped, why in checks:
                if script is not None and holds(script, self.variables) == when:
                    self.feedback_message = why
                    return status, skipped
        elif self.while_ is not None and not holds(self.while_, self.variables):
            self.decorated.stop(Status.INVALID)
            self.run(self.on_halted)
            self.feedback_message = "halted: _while is false"
            return Status.SUCCESS, True
        return None

    def run(self, script: CompiledScript | None) -> None:
        """Run a post-condition script, when there is one."""
        if script is not None:
            script.run(self.variables)

    def stop(self, new_status: Status) -> None:
        """Stop; a halt (INVALID) while RUNNING halts the node, then runs ``on_halted``."""
        halted = new_status == Status.INVALID and self.status == Status.RUNNING
        super().stop(new_status)
        if halted:
            self.run(self.on_halted)
