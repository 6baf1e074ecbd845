"""BT.CPP 4's branching controls: IfThenElse, WhileDoElse and Switch2..Switch6.

The first child of :class:`IfThenElse` and :class:`WhileDoElse` is the condition; a
condition that is SKIPPED is an error in BT.CPP (it reports a logic error), so it is one
here too. :class:`Switch` compares a variable with its cases as BT.CPP does: equal
strings, or equal as integers (the text's leading integer, as ``std::from_chars`` reads
it), or equal as reals within float epsilon.
"""

from __future__ import annotations

import re
from collections.abc import Sequence as Children
from typing import Any

from sar_framework.engine.nodes.controls.base import Behaviour, BtControl, Outcome, Steps
from sar_framework.engine.variables import Variables


class _Branching(BtControl):
    """A condition (the first child) choosing between a branch and an optional else-branch.

    Args:
        name: The behaviour's name.
        children: Condition, then-branch and optional else-branch.

    Raises:
        ValueError: Not 2 or 3 children.
    """

    def __init__(self, name: str, children: Children[Behaviour]) -> None:
        if len(children) not in (2, 3):
            raise ValueError(f"'{name}' needs 2 or 3 children (condition, then, else), "
                             f"got {len(children)}")
        super().__init__(name, children)

    def tick_condition(self) -> Steps:
        """Tick the condition; return its outcome (SKIPPED is an error, as in BT.CPP)."""
        condition = yield from self.tick_child(self.children[0])
        if condition is Outcome.SKIPPED:
            raise RuntimeError(f"{type(self).__name__} '{self.name}': its condition was "
                               "skipped")
        return condition

    def tick_branch(self, index: int) -> Steps:
        """Tick the branch at ``index``; once it is not running, reset every child."""
        result = yield from self.tick_child(self.children[index])
        if result is not Outcome.RUNNING:
            self.reset_children()
        return result


class IfThenElse(_Branching):
    """BT.CPP ``IfThenElse``: the condition once, then the chosen branch until it completes.

    Without a third child a failing condition fails the node.
    """

    def __init__(self, name: str, children: Children[Behaviour]) -> None:
        super().__init__(name, children)
        self.branch = 0

    def control(self) -> Steps:
        """Tick the condition (unless a branch is running), then the branch."""
        if self.branch == 0:
            condition = yield from self.tick_condition()
            if condition is Outcome.RUNNING or (condition is Outcome.FAILURE
                                                and len(self.children) != 3):
                return condition
            self.branch = 1 if condition is Outcome.SUCCESS else 2
        result = yield from self.tick_branch(self.branch)
        if result is not Outcome.RUNNING:
            self.branch = 0
        return result

    def halt(self) -> None:
        """Back to the condition; children halted and reset."""
        self.branch = 0
        super().halt()


class WhileDoElse(_Branching):
    """BT.CPP ``WhileDoElse``: the condition every tick; switching branch halts the other."""

    def control(self) -> Steps:
        """Tick the condition, then the branch it selects."""
        condition = yield from self.tick_condition()
        if condition is Outcome.RUNNING:
            return condition
        three = len(self.children) == 3
        if condition is Outcome.SUCCESS:
            if three:
                self.halt_child(2)
            return (yield from self.tick_branch(1))
        if not three:
            self.reset_children()
            return Outcome.FAILURE
        self.halt_child(1)
        return (yield from self.tick_branch(2))


_INTEGER = re.compile(r"-?[0-9]+")
_REAL = re.compile(r"-?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][-+]?[0-9]+)?|-?(?:inf|nan)",
                   re.IGNORECASE)
_FLOAT_EPSILON = 1.1920928955078125e-07
_INT32 = 2**31


def _leading_int(text: str) -> int | None:
    match = _INTEGER.match(text)
    if match is None:
        return None
    value = int(match.group())
    return value if -_INT32 <= value < _INT32 else None


def _leading_real(text: str) -> float | None:
    match = _REAL.match(text)
    return float(match.group()) if match is not None else None


def case_matches(variable: str, case: str) -> bool:
    """BT.CPP's Switch comparison: equal text, equal leading integers, or close reals."""
    if variable == case:
        return True
    left, right = _leading_int(variable), _leading_int(case)
    if left is not None and right is not None and left == right:
        return True
    real_left, real_right = _leading_real(variable), _leading_real(case)
    return (real_left is not None and real_right is not None
            and abs(real_left - real_right) <= _FLOAT_EPSILON)


def as_text(value: Any) -> str:
    """A variable's value as the string BT.CPP's ``getInput<std::string>`` would give."""
    if isinstance(value, bool):
        return "true" if value else "false"
    return str(value)


class Switch(BtControl):
    """BT.CPP ``Switch2``..``Switch6``: tick the child of the first case the variable matches.

    The last child is the default (no case matches, or the variable is unset). A change
    of case halts the child that was running.

    Args:
        name: The behaviour's name.
        children: One child per case, then the default.
        cases: The case values (``case_1``, ``case_2``, ...).
        variable: The variable's name in ``variables``.
        variables: Where the variable is read (and the cases named by ``case_variables``).
        case_variables: Per case, the name in ``variables`` to read it from at each tick
            (its entry unset: the case is passed over, as BT.CPP does), or None for the
            literal of ``cases``.

    Raises:
        ValueError: The number of children is not the number of cases plus one.
    """

    marks_running = False

    def __init__(self, name: str, children: Children[Behaviour], cases: Children[str],
                 variable: str, variables: Variables,
                 *, case_variables: Children[str | None] = ()) -> None:
        if len(children) != len(cases) + 1:
            raise ValueError(f"'{name}' has {len(cases)} cases: it needs {len(cases) + 1} "
                             f"children (one per case, then the default), got {len(children)}")
        super().__init__(name, children)
        self.cases = [as_text(case) for case in cases]
        self.case_variables = list(case_variables) + [None] * (len(cases) - len(case_variables))
        self.variable = variable
        self.variables = variables
        self.running = -1

    def choose(self) -> int:
        """The index of the child to tick this time."""
        if self.variable in self.variables:
            value = as_text(self.variables.get(self.variable))
            for index, literal in enumerate(self.cases):
                read = self.case_variables[index]
                if read is not None and read not in self.variables:
                    continue
                case = literal if read is None else as_text(self.variables.get(read))
                if case_matches(value, case):
                    return index
        return len(self.cases)

    def control(self) -> Steps:
        """Tick the matching child; halt the previously running one if it changed."""
        chosen = self.choose()
        if self.running not in (-1, chosen):
            self.halt_child(self.running)
        result = yield from self.tick_child(self.children[chosen])
        if result is Outcome.SKIPPED:
            self.running = -1
        elif result is Outcome.RUNNING:
            self.running = chosen
        else:
            self.reset_children()
            self.running = -1
        return result

    def halt(self) -> None:
        """Forget the running case; children halted and reset."""
        self.running = -1
        super().halt()
