"""The parsed form of a script: one small class per kind of expression, each evaluating itself.

Every node keeps the 1-based line and column of the token that names it (the operator,
the variable, the literal), so an error at run time points where the parser would.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from . import values
from .errors import ScriptError

if TYPE_CHECKING:  # py_trees' blackboard: only when a script runs
    from ..variables import Variables

#: Assignment operators and the arithmetic each compound one applies.
COMPOUND = {"+=": "+", "-=": "-", "*=": "*", "/=": "/"}


@dataclass(frozen=True)
class Position:
    """Where a node's token starts: 1-based line and column in the script."""

    line: int
    column: int


@dataclass
class Environment:
    """What a script runs against: its variables and the enum names it was compiled with."""

    variables: Variables
    enums: Mapping[str, int]


class Node:
    """An expression: evaluates to a value, or raises :class:`ScriptError` at its position."""

    position: Position

    def evaluate(self, env: Environment) -> Any:
        """Return this expression's value in ``env``."""
        raise NotImplementedError

    def fail(self, message: str) -> ScriptError:
        """A :class:`ScriptError` at this node."""
        return ScriptError(message, self.position.column, self.position.line)

    def run(self, env: Environment) -> Any:
        """Evaluate, turning an :class:`~.values.OperationError` into a positioned error."""
        try:
            return self.evaluate(env)
        except values.OperationError as error:
            raise self.fail(str(error)) from None
        except OverflowError:
            raise self.fail("a number is too large") from None


@dataclass
class Literal(Node):
    """A number, string, ``true``/``false`` or enum name."""

    value: Any
    position: Position

    def evaluate(self, env: Environment) -> Any:
        """Return the literal's value."""
        return self.value


@dataclass
class Name(Node):
    """A variable read (``@name`` reads the root blackboard's entry)."""

    name: str
    position: Position

    def evaluate(self, env: Environment) -> Any:
        """Return the variable's value; an unset variable is an error."""
        try:
            return env.variables.get(self.name)
        except KeyError:
            raise self.fail(f"variable {self.name!r} has no value") from None


@dataclass
class Unary(Node):
    """Prefix ``-``, ``~`` or ``!``."""

    op: str
    operand: Node
    position: Position

    def evaluate(self, env: Environment) -> Any:
        """Apply the operator to the operand's value."""
        return values.unary(self.op, self.operand.run(env))


@dataclass
class Binary(Node):
    """An infix operator other than a comparison: both sides are always evaluated."""

    op: str
    left: Node
    right: Node
    position: Position

    def evaluate(self, env: Environment) -> Any:
        """Evaluate both sides (left first), then apply the operator."""
        left = self.left.run(env)
        right = self.right.run(env)
        if self.op in ("+", "-", "*", "/"):
            return values.arithmetic(self.op, left, right)
        if self.op in ("&", "|", "^"):
            return values.bitwise(self.op, left, right)
        if self.op in ("&&", "||"):
            return values.logical(self.op, left, right)
        return values.concat(left, right)


@dataclass
class Compare(Node):
    """A chain ``a < b <= c``: true when every link holds; stops at the first that fails."""

    operands: list[Node]
    ops: list[tuple[str, Position]]
    position: Position

    def evaluate(self, env: Environment) -> Any:
        """Evaluate operands left to right while the links hold."""
        left = self.operands[0].run(env)
        for (op, where), operand in zip(self.ops, self.operands[1:], strict=True):
            right = operand.run(env)
            try:
                holds = values.compare(op, left, right, env.enums)
            except values.OperationError as error:
                raise ScriptError(str(error), where.column, where.line) from None
            if not holds:
                return False
            left = right
        return True


@dataclass
class Conditional(Node):
    """``condition ? then : otherwise`` (only the chosen branch is evaluated)."""

    condition: Node
    then: Node
    otherwise: Node
    position: Position

    def evaluate(self, env: Environment) -> Any:
        """Evaluate the condition, then one branch."""
        chosen = values.branch_truth(self.condition.run(env), env.enums)
        return (self.then if chosen else self.otherwise).run(env)


@dataclass
class Assign(Node):
    """``name := value``, ``name = value`` or a compound ``name += value``."""

    op: str
    name: str
    value: Node
    position: Position

    def evaluate(self, env: Environment) -> Any:
        """Store the value (fitted to the entry's type) and return what was stored."""
        variables = env.variables
        if self.op in COMPOUND and self.name not in variables:
            raise self.fail(f"{self.name!r} has no value for '{self.op}'")
        value = self.value.run(env)
        old = variables.get(self.name) if self.name in variables else None
        if self.op in COMPOUND:
            value = values.updated(COMPOUND[self.op], self.name, old, value)
        new = values.stored(self.name, old, value, env.enums)
        try:
            variables.set(self.name, new)
        except (KeyError, AttributeError, TypeError) as error:
            raise self.fail(f"cannot write {self.name!r}: {error}") from None
        return new
