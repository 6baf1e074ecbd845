"""BehaviorTree.CPP 4's script language, parsed with lark and evaluated without ``eval``.

A script is one or more expressions separated by ``;``::

    count := count + 1; done = count >= 3 && !aborted

:func:`compile_script` parses it once (:class:`ScriptError` with the 1-based line and
column on a bad script); the :class:`CompiledScript` says which variables it reads and
writes, checks itself against declared types (:meth:`CompiledScript.check`) and runs
against a :class:`~sar_framework.engine.variables.Variables` (:meth:`CompiledScript.run`).
:func:`as_condition` judges a script's value the way BT.CPP's conditions do. The language
and where it departs from BT.CPP 4.7.3 are described in ``docs/reference/scripts.md``.
"""

from __future__ import annotations

from typing import Any

from .compiled import CompiledScript, compile_script
from .errors import ScriptError
from .values import OperationError, to_bool

__all__ = ["CompiledScript", "ScriptError", "as_condition", "compile_script"]


def as_condition(script: CompiledScript, value: Any) -> bool:
    """``value`` (what ``script`` returned) as a condition, as BT.CPP casts it to bool.

    Args:
        script: The script that gave the value (for the error's position).
        value: Its value.

    Returns:
        True or False.

    Raises:
        ScriptError: When the value is not a boolean: a string, an integer other than 0
            and 1, or another type.
    """
    try:
        return to_bool(value)
    except OperationError as error:
        where = script.last_position()
        raise ScriptError(f"the condition's value: {error}", where.column, where.line,
                          script.text) from None
