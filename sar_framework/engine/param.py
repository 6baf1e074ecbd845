"""One parameter declaration for the whole project: a leaf's params and every node's.

A :class:`Param` says a parameter's name, type, default, unit, range and meaning once. A leaf
plugin lists them in ``@leaf(params=[...])`` (:mod:`.plugin`); each ROS node of the mission
lists them in one table in a ROS-free module (the runner's, the simulator's, the servers',
the recorder's), and everything else reads that table: the node's ROS declarations (with
descriptors and ranges), ``sar-tree run``'s checks, the launch file's defaults, the help
texts and the documentation tables.

:meth:`Param.problem` is the one rule for a value, worded for a user::

    >>> Param("speed", float, default=20.0, exclusive_minimum=0.0).problem(0)
    'must be > 0, got 0'

A leaf param is a scalar (``str``, ``int``, ``float``, ``bool``) or a reference to another
leaf; a node parameter may also be a list (``list[str]``, ``list[int]``) or either of two
types (``str | list[str]``), as ROS parameters can be.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from sar_framework.engine.diagnostics import did_you_mean


class _Required:
    """Sentinel type for a param without a default."""

    def __repr__(self) -> str:
        return "REQUIRED"


#: Default of a param that must be given.
REQUIRED: Any = _Required()

#: The scalar types a param may have, with the JSON Schema type each maps to.
PARAM_TYPES: dict[type, str] = {str: "string", int: "integer", float: "number", bool: "boolean"}

#: The further types a node parameter may have (ROS arrays, or a string or a list of them).
LIST_TYPES: tuple[Any, ...] = (list[str], list[int], str | list[str])

_WORDS: dict[Any, str] = {
    str: "a string", int: "an integer", float: "a number", bool: "true or false",
    list[str]: "a list of strings", list[int]: "a list of integers",
    str | list[str]: "a string or a list of strings",
}


def type_name(kind: Any) -> str:
    """``float``, ``list[str]``, ``str | list[str]``: a param type as a user reads it."""
    return kind.__name__ if isinstance(kind, type) else str(kind)


def _is(kind: Any, value: Any) -> bool:
    """Whether ``value`` is of ``kind`` (an integer is a number; a bool is not)."""
    if kind is float:
        return isinstance(value, (int, float)) and not isinstance(value, bool)
    if kind is int:
        return isinstance(value, int) and not isinstance(value, bool)
    if kind == list[str]:
        return isinstance(value, list) and all(isinstance(v, str) for v in value)
    if kind == list[int]:
        return isinstance(value, list) and all(_is(int, v) for v in value)
    if kind == str | list[str]:
        return _is(str, value) or _is(list[str], value)
    return isinstance(value, kind)


@dataclass(frozen=True)
class Param:
    """Declaration of one parameter (of a leaf plugin or of a node).

    Attributes:
        name: The key (a tree file's, or the ROS parameter's dotted name; in a node's table
            ``*`` stands for one name segment, as in ``shelves.*.x``).
        type: ``str``, ``int``, ``float``, ``bool``; for a node parameter also one of
            :data:`LIST_TYPES`. Ignored for references.
        default: The value when none is given; :data:`REQUIRED` if it must be given; None
            for a node parameter that is unset unless given (the node then says what it uses).
        description: One line for docs, schema, help and the ROS parameter descriptor.
        minimum: Inclusive lower bound for numbers.
        maximum: Inclusive upper bound for numbers.
        exclusive_minimum: Exclusive lower bound for numbers (e.g. a rate > 0).
        enum: The allowed values, when the set is closed.
        ref: For a reference param: the plugin name the referenced leaf must have.
            The value in the tree is that leaf's ``id``.
        unit: The unit of a number (``s``, ``m``, ``Hz``, ``rad``...), "" when it has none.
    """

    name: str
    type: Any = str
    default: Any = REQUIRED
    description: str = ""
    minimum: float | None = None
    maximum: float | None = None
    exclusive_minimum: float | None = None
    enum: tuple[Any, ...] | None = None
    ref: str | None = None
    unit: str = ""

    def __post_init__(self) -> None:
        if self.ref is None and self.type not in PARAM_TYPES and self.type not in LIST_TYPES:
            raise TypeError(f"param {self.name!r}: unsupported type {self.type!r}")
        if self.ref is not None and self.default is not REQUIRED and self.default is not None:
            raise TypeError(f"param {self.name!r}: a reference can only default to None")
        if self.ref is None and self.default not in (REQUIRED, None) \
                and self.problem(self.default) is not None:
            raise TypeError(f"param {self.name!r}: default {self.default!r} "
                            f"{self.problem(self.default)}")

    @property
    def required(self) -> bool:
        """Whether the param must be given."""
        return self.default is REQUIRED

    @property
    def is_reference(self) -> bool:
        """Whether the value names another leaf's ``id``."""
        return self.ref is not None

    def bounds(self) -> str:
        """The range as text (``> 0``, ``>= 0 and <= 1``), "" when unbounded."""
        parts = []
        if self.exclusive_minimum is not None:
            parts.append(f"> {self.exclusive_minimum:g}")
        elif self.minimum is not None:
            parts.append(f">= {self.minimum:g}")
        if self.maximum is not None:
            parts.append(f"<= {self.maximum:g}")
        return " and ".join(parts)

    def problem(self, value: Any) -> str | None:
        """What is wrong with ``value`` for this param, or None: type, range, choices.

        Args:
            value: The value given (a reference param's value is a leaf id, a string).

        Returns:
            ``must be a number, got 'abc'``, ``must be > 0, got 0``, ... or None.
        """
        kind = str if self.ref is not None else self.type
        if not _is(kind, value):
            return f"must be {_WORDS[kind]}, got {value!r}"
        if kind is float and not math.isfinite(value):
            return f"must be finite, got {value!r}"
        if kind in (int, float):
            too_low = ((self.exclusive_minimum is not None and value <= self.exclusive_minimum)
                       or (self.minimum is not None and value < self.minimum))
            too_high = self.maximum is not None and value > self.maximum
            if too_low or too_high:
                return f"must be {self.bounds()}, got {value!r}"
        if self.enum is not None and value not in self.enum:
            choices = [str(c) for c in self.enum]
            return (f"must be one of {', '.join(choices)}, got {value!r}"
                    + did_you_mean(str(value), choices))
        return None
