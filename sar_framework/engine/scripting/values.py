"""What the script language's operators do to values, as BehaviorTree.CPP 4.7.3 does it.

BT.CPP keeps numbers as ``int64`` or ``double`` and strings as strings; Python's ``int``
(``bool`` included: ``true`` is BT.CPP's integer 1), ``float`` and ``str`` play those parts.
Any other value (a list, a ROS message) can be read, compared with nothing, and copied
into an entry of its own type. Every function here raises :class:`OperationError` with a
message for the tree author; the evaluator adds the position.

Where the two differ on purpose (see ``docs/reference/scripts.md``): an operation on two integers
(``+ - *``, prefix ``-``, bitwise) gives an integer where BT.CPP gives a ``double`` of the
same value, and comparisons and logic give ``True``/``False`` where BT.CPP gives 1.0/0.0.
"""

from __future__ import annotations

import math
import numbers
import re
from collections.abc import Mapping
from typing import Any

#: BT.CPP compares numbers with ``|a - b| <= FLT_EPSILON`` (scripting/operators.hpp).
EQUALITY_TOLERANCE = 1.1920928955078125e-07
INT64_MIN, INT64_MAX = -(2**63), 2**63 - 1
_NUMBER_TEXT = re.compile(r"[+-]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?")


class OperationError(Exception):
    """An operator met values it does not apply to (the message says which)."""


def is_number(value: Any) -> bool:
    """Whether ``value`` is a number for the script language (``bool`` included)."""
    return isinstance(value, numbers.Real)


def type_name(value: Any) -> str:
    """The name a message uses for ``value``'s type (``int``, ``str``, ``Path``...)."""
    return type(value).__name__


def a_type(value: Any) -> str:
    """``value``'s type name with its article (``an int``, ``a str``)."""
    name = type_name(value)
    return ("an " if name[:1].lower() in "aeiou" else "a ") + name


def describe(value: Any) -> str:
    """``value`` and its type, as a message shows them."""
    shown = repr(value)
    if len(shown) > 40:
        shown = shown[:37] + "..."
    return f"{type_name(value)} {shown}"


def string_to_number(text: str, enums: Mapping[str, int]) -> int | float:
    """A string used as a number: ``true``/``false``, an enum name, or a number's text."""
    if text == "true":
        return 1
    if text == "false":
        return 0
    if text in enums:
        return enums[text]
    if _NUMBER_TEXT.fullmatch(text):
        number = float(text)
        return int(number) if number.is_integer() and re.fullmatch(r"[+-]?[0-9]+", text) else number
    raise OperationError(f"the string {text!r} is not a number")


def to_bool(value: Any) -> bool:
    """A value used as a condition, as BT.CPP casts it to ``bool``.

    Floats are true when not zero; integers must be 0 or 1 (BT.CPP refuses to narrow 2 to
    a bool); strings and other values are not conditions.
    """
    if isinstance(value, bool):
        return value
    if isinstance(value, numbers.Integral):
        if value in (0, 1):
            return bool(value)
        raise OperationError(f"{value} is not a boolean (an integer condition must be 0 or 1)")
    if isinstance(value, numbers.Real):
        return value != 0
    raise OperationError(f"{describe(value)} is not a boolean")


def branch_truth(value: Any, enums: Mapping[str, int]) -> bool:
    """A value as the condition of ``?:`` (any number not zero; a string read as a number)."""
    if isinstance(value, str):
        value = string_to_number(value, enums)
    if is_number(value):
        return value != 0
    raise OperationError(f"{describe(value)} cannot be the condition of '?:'")


def to_int64(value: Any, what: str) -> int:
    """``value`` as a 64-bit integer, for bitwise operators (no fraction may be lost)."""
    if not is_number(value):
        raise OperationError(f"{what} needs numbers, not {describe(value)}")
    if not isinstance(value, numbers.Integral) and (
            not math.isfinite(value) or not float(value).is_integer()):
        raise OperationError(f"{what} needs integers, not {value}")
    if not INT64_MIN <= value <= INT64_MAX:
        raise OperationError(f"{what} needs 64-bit integers, not {value}")
    return int(value)


def _check_int64(value: int) -> int:
    if not INT64_MIN <= value <= INT64_MAX:
        raise OperationError(f"{value} is out of the 64-bit integer range")
    return value


def unary(op: str, value: Any) -> Any:
    """Prefix ``-`` (negate), ``~`` (bitwise complement) or ``!`` (logical not)."""
    if isinstance(value, str):
        raise OperationError(f"prefix '{op}' does not apply to a string")
    if not is_number(value):
        raise OperationError(f"prefix '{op}' does not apply to {describe(value)}")
    if op == "-":
        return -int(value) if isinstance(value, numbers.Integral) else -float(value)
    if op == "~":
        if not (INT64_MIN <= value <= INT64_MAX):
            raise OperationError(f"{value} is out of range for '~'")
        return ~int(value)  # BT.CPP truncates a double here (~2.5 is -3)
    return not value


def _divide(left: float, right: float) -> float:
    if right != 0:
        return left / right
    if left == 0 or math.isnan(left):
        return math.nan
    return math.copysign(math.inf, left) * math.copysign(1.0, right)


def arithmetic(op: str, left: Any, right: Any) -> Any:
    """``+ - * /`` on numbers; ``+`` also joins two strings."""
    if is_number(left) and is_number(right):
        if op == "/":
            return _divide(float(left), float(right))
        both_int = isinstance(left, numbers.Integral) and isinstance(right, numbers.Integral)
        a, b = (int(left), int(right)) if both_int else (float(left), float(right))
        result = a + b if op == "+" else a - b if op == "-" else a * b
        if both_int and not INT64_MIN <= result <= INT64_MAX:
            return float(result)  # past int64, BT.CPP's double arithmetic goes on
        return result
    if op == "+" and isinstance(left, str) and isinstance(right, str):
        return left + right
    raise OperationError(f"'{op}' does not apply to {describe(left)} and {describe(right)}")


def bitwise(op: str, left: Any, right: Any) -> int:
    """``& | ^`` on integers (floats without a fraction count as integers)."""
    a = to_int64(left, f"'{op}'")
    b = to_int64(right, f"'{op}'")
    return a & b if op == "&" else a | b if op == "|" else a ^ b


def logical(op: str, left: Any, right: Any) -> bool:
    """``&&`` and ``||``: both operands are evaluated and must be numbers, as in BT.CPP."""
    if not (is_number(left) and is_number(right)):
        raise OperationError(f"'{op}' does not apply to {describe(left)} and {describe(right)}")
    return (to_bool(left) and to_bool(right)) if op == "&&" else (to_bool(left) or to_bool(right))


def as_text(value: Any) -> str:
    """A string or number as ``..`` writes it (a double as C++'s ``std::to_string``)."""
    if isinstance(value, str):
        return value
    if isinstance(value, numbers.Integral):
        return str(int(value))
    return f"{float(value):f}"


def concat(left: Any, right: Any) -> str:
    """``..``: joins two strings, or a string and a number."""
    texts = isinstance(left, str) or isinstance(right, str)
    if texts and (is_number(left) or isinstance(left, str)) and (
        is_number(right) or isinstance(right, str)
    ):
        return as_text(left) + as_text(right)
    raise OperationError(f"'..' needs a string and a string or number, not {describe(left)} "
                         f"and {describe(right)}")


def _holds(op: str, a: Any, b: Any) -> bool:
    if op == "==":
        return bool(a == b)
    if op == "!=":
        return bool(a != b)
    return bool(a < b if op == "<" else a > b if op == ">" else a <= b if op == "<=" else a >= b)


def compare(op: str, left: Any, right: Any, enums: Mapping[str, int]) -> bool:
    """One comparison; a string against a number is read as a number (enum names too)."""
    if isinstance(left, str) and isinstance(right, str):
        return _holds(op, left, right)
    if isinstance(left, str) and is_number(right):
        left = string_to_number(left, enums)
    elif isinstance(right, str) and is_number(left):
        right = string_to_number(right, enums)
    if not (is_number(left) and is_number(right)):
        raise OperationError(f"cannot compare {describe(left)} with {describe(right)}")
    a, b = float(left), float(right)
    if op in ("==", "!="):
        same = abs(a - b) <= EQUALITY_TOLERANCE or a == b
        return same if op == "==" else not same
    return _holds(op, a, b)


def stored(name: str, old: Any, new: Any, enums: Mapping[str, int]) -> Any:
    """The value ``name`` holds after ``name = new`` when it held ``old``.

    An entry keeps its type, as BT.CPP's entries do: a string goes into a number entry
    only when it reads as a number; a float into an int entry only without a fraction;
    a number into a bool entry only when it is 0 or 1; any other type only as itself.
    """
    if old is None:
        return new
    if isinstance(new, str) and is_number(old):
        new = string_to_number(new, enums)
    problem = f"cannot store {describe(new)} in {name!r}, which holds {a_type(old)}"
    if isinstance(old, str):
        if not isinstance(new, str):
            raise OperationError(problem)
        return new
    if isinstance(old, bool):
        if not is_number(new) or new not in (0, 1):
            raise OperationError(problem)
        return bool(new)
    if isinstance(old, numbers.Integral):
        if not is_number(new):
            raise OperationError(problem)
        if isinstance(new, numbers.Integral):
            return _check_int64(int(new))
        if not math.isfinite(new) or not float(new).is_integer():
            raise OperationError(problem)
        return _check_int64(int(new))
    if isinstance(old, numbers.Real):
        if not is_number(new):
            raise OperationError(problem)
        return float(new)
    if not isinstance(new, type(old)):
        raise OperationError(problem)
    return new


def updated(op: str, name: str, old: Any, value: Any) -> Any:
    """The result of ``name op= value`` (before :func:`stored` fits it to the entry)."""
    if isinstance(value, str):
        if op != "+":
            raise OperationError(f"'{op}=' does not apply to strings")
        if not isinstance(old, str):
            raise OperationError(f"'+=' with a string needs a string in {name!r}, which "
                                 f"holds {describe(old)}")
        return old + value
    if not is_number(value) or not is_number(old):
        raise OperationError(f"'{op}=' needs numbers: {name!r} holds {describe(old)}, the "
                             f"right side is {describe(value)}")
    return arithmetic(op, old, value)
