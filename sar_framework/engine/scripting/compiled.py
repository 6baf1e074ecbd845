"""A compiled script: what it reads and writes, a static check, and running it."""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

from . import nodes, typecheck
from .errors import ScriptError
from .parser import parse

if TYPE_CHECKING:  # py_trees' blackboard: only when a script runs
    from ..variables import Variables


class CompiledScript:
    """A script parsed once and run many times (never through ``eval``).

    Build one with :func:`compile_script`.

    Attributes:
        text: The script as written.
        reads: The variables it reads, in order of first use (``@name`` is the root
            blackboard's ``name``; enum names are not variables). A compound assignment
            (``x += 1``) reads and writes.
        writes: The variables it assigns, in order of first assignment.
        enums: The enum names it was compiled with.
    """

    def __init__(self, text: str, enums: Mapping[str, int] | None = None) -> None:
        self.text = text
        self.enums: Mapping[str, int] = MappingProxyType(dict(enums or {}))
        parsed = parse(text, self.enums)
        self.statements = parsed.statements
        self.reads: tuple[str, ...] = tuple(parsed.reads)
        self.writes: tuple[str, ...] = tuple(parsed.writes)

    def __repr__(self) -> str:
        return f"CompiledScript({self.text!r})"

    def check(self, types: Mapping[str, str], *, closed: bool = True,
              condition: bool = False) -> list[ScriptError]:
        """Return the script's static type problems (an empty list when there are none).

        Args:
            types: Each known variable's type name, as ports declare them: ``int``,
                ``float``, ``bool``, ``str``, ``list``, ``object`` (anything), or a ROS
                message type ``pkg/msg/Type``. Keys are names as the script writes them
                (``@goal`` for the root blackboard's ``goal``).
            closed: When true, reading or ``=``-assigning a variable that ``types`` does
                not name is a problem; ``:=`` may always create a variable (its type is
                then the value's).
            condition: When true, the script is a condition (``ScriptCondition``'s code,
                ``Precondition``'s ``if``, ``_skipIf``...): its last value must be a
                number or true/false, not a string or another type.

        Returns:
            One :class:`ScriptError` per problem, in script order.
        """
        return typecheck.check(self.statements, self.text, types, closed=closed,
                               condition=condition)

    def run(self, variables: Variables) -> Any:
        """Run every statement in order; return the value of the last one.

        Args:
            variables: What the script reads and writes.

        Returns:
            The last statement's value.

        Raises:
            ScriptError: When a statement fails (an unset variable, a type clash); the
                statements before it have run.
        """
        env = nodes.Environment(variables, self.enums)
        result: Any = None
        try:
            for statement in self.statements:
                result = statement.run(env)
        except ScriptError as error:
            raise error.in_script(self.text) from None
        except RecursionError:
            raise ScriptError("the script is nested too deeply", 1, 1, self.text) from None
        return result

    def last_position(self) -> nodes.Position:
        """Where the last statement starts (the value a condition is judged on)."""
        return self.statements[-1].position


def compile_script(text: str, *, enums: Mapping[str, int] | None = None) -> CompiledScript:
    """Parse ``text`` as a BehaviorTree.CPP 4 script.

    Args:
        text: The script (``"count := count + 1; done = count >= 3"``).
        enums: Enum names the script may use, each with its integer value (BT.CPP's
            ``registerScriptingEnum``); a name here is a constant, never a variable.

    Returns:
        The compiled script.

    Raises:
        ScriptError: With a message and the 1-based line and column, for a syntax error,
            operators of different groups mixed without parentheses, an assignment to
            something other than a variable, or a number literal out of range.
    """
    return CompiledScript(text, enums)
