"""Ports: the blackboard entries a leaf reads and writes, declared beside its params.

A leaf declares its ports in :func:`.plugin.leaf` (BT.CPP's ``providedPorts()``)::

    @leaf(ports=[
        InputPort("goal", "geometry_msgs/msg/PoseStamped", description="Where to plan to."),
        OutputPort("path", "nav_msgs/msg/Path", description="The planned path."),
        InputPort("hz", float, default=1.0),
    ])

A tree file binds each port with BT.CPP's syntax: a literal (``hz: 1.0``), an entry of
the node's scope (``goal: "{goal}"``), an entry of the root scope (``"{@goal}"``) or the
entry named like the port (``"{=}"``). A port type is a type name: ``str int float bool
list any`` (Python's ``str int float bool list object`` are accepted and named so) or a
ROS message type by name, ``pkg/msg/Type``; the engine never imports the message.

Literals convert as BT.CPP's ``convertFromString`` does for the basic types: an ``int``
from decimal digits (the whole text, stricter than ``from_chars``), a ``float`` from any
number text, a ``bool`` from ``true/True/TRUE/1`` or ``false/False/FALSE/0``, a ``list``
from ``a;b;c``. A message type's literal is its fields as a mapping, a pose shorthand or
a text form (:mod:`.message_literals`), kept as a :class:`.MessageLiteral`. Types are
compatible when equal, when either is ``any``, or ``int -> float``.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from enum import Enum
from typing import Any

from sar_framework.engine.message_literals import message_literal

#: The basic port type names, in the order the docs list them.
BASIC_TYPES: tuple[str, ...] = ("str", "int", "float", "bool", "list", "any")
#: Python types accepted in a declaration, with the type name each stands for.
PYTHON_TYPES: dict[type, str] = {
    str: "str", int: "int", float: "float", bool: "bool", list: "list", object: "any",
}  # fmt: skip
#: A ROS message type by name (``geometry_msgs/msg/PoseStamped``).
MESSAGE_TYPE = re.compile(r"^[A-Za-z][A-Za-z0-9_]*/msg/[A-Z][A-Za-z0-9_]*$")
#: An entry name: what ``{name}`` may hold (no '.', which py_trees reads as an attribute).
ENTRY_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
#: An entry reference as written: ``{name}``, ``{@name}`` or ``{=}``.
ENTRY_REF = re.compile(r"^\{(?P<root>@?)(?P<name>[^{}]*)\}$")


class Naming(str, Enum):
    """How a port's text is read: a value, or the name of an entry (BT.CPP's own nodes).

    BT.CPP reads some ports of its own nodes as *entry names*: ``SetBlackboard``'s
    ``output_key``, ``UnsetBlackboard``'s ``key``, the ``entry`` of ``SkipUnlessUpdated``,
    ``WaitValueUpdate`` and ``WasEntryUpdated``.
    """

    #: A literal value, or ``{name}`` for an entry (every leaf's port).
    VALUE = "value"
    #: The entry's name: ``x`` and ``{x}`` both name x (BT.CPP strips the braces).
    NAME = "name"
    #: The entry's name, bare: ``x`` names x. BT.CPP would read ``{x}`` as the entry whose
    #: name x holds, which static resolution cannot follow: refused.
    BARE_NAME = "bare name"


class _NoDefault:
    def __repr__(self) -> str:
        return "NO_DEFAULT"


#: The default of a port that has none.
NO_DEFAULT: Any = _NoDefault()


class Direction(str, Enum):
    """Which way data flows through a port."""

    INPUT = "input"
    OUTPUT = "output"
    INOUT = "inout"

    @property
    def reads(self) -> bool:
        """Whether the node reads the entry."""
        return self is not Direction.OUTPUT

    @property
    def writes(self) -> bool:
        """Whether the node writes the entry."""
        return self is not Direction.INPUT


def type_name(declared: type | str) -> str:
    """Return the port type name of a declared type.

    Args:
        declared: A Python type from :data:`PYTHON_TYPES`, a basic type name or a
            message type name.

    Returns:
        The type name.

    Raises:
        TypeError: The type is none of those.
    """
    if isinstance(declared, type):
        if declared in PYTHON_TYPES:
            return PYTHON_TYPES[declared]
        raise TypeError(f"unsupported port type {declared!r}")
    if declared in BASIC_TYPES or (isinstance(declared, str) and MESSAGE_TYPE.match(declared)):
        return declared
    raise TypeError(f"unsupported port type {declared!r} (expected one of "
                    f"{', '.join(BASIC_TYPES)} or pkg/msg/Type)")


def valid_type(name: Any) -> bool:
    """Whether ``name`` is a port type name."""
    return isinstance(name, str) and (name in BASIC_TYPES or bool(MESSAGE_TYPE.match(name)))


def is_message(name: str) -> bool:
    """Whether a type name is a ROS message type."""
    return "/" in name


def compatible(written: str, read: str) -> bool:
    """Whether a value of type ``written`` may be read as ``read``."""
    return written == read or "any" in (written, read) or (written, read) == ("int", "float")


_TRUE = ("true", "True", "TRUE", "1")
_FALSE = ("false", "False", "FALSE", "0")
_INT = re.compile(r"^[+-]?[0-9]+$")


def convert(type_: str, value: Any) -> Any:
    """Convert a literal (a YAML scalar, list or, for a message, mapping) to a port type.

    Args:
        type_: The port type name.
        value: The literal as the tree file gives it.

    Returns:
        The value, of the port's type.

    Raises:
        ValueError: With the reason, when the literal does not convert (for a message, a
            :class:`.LiteralError` with each problem's path).
    """
    if type_ == "any":
        return value
    if is_message(type_):
        return message_literal(type_, value)
    if type_ == "list":
        if isinstance(value, list):
            return value
        if isinstance(value, str):
            return value.split(";") if value else []
        raise ValueError(f"expected a list or 'a;b;c', got {_shown(value)}")
    article = "an" if type_ == "int" else "a"
    if isinstance(value, (list, dict)) or value is None:
        raise ValueError(f"expected {article} {type_}, got {_shown(value)}")
    if type_ == "str":
        if isinstance(value, bool):
            return "true" if value else "false"
        return value if isinstance(value, str) else str(value)
    if type_ == "bool":
        if isinstance(value, bool):
            return value
        if str(value) in _TRUE or str(value) in _FALSE:
            return str(value) in _TRUE
        raise ValueError(f"expected a bool (true/false/1/0), got {_shown(value)}")
    if isinstance(value, bool):
        raise ValueError(f"expected {article} {type_}, got {_shown(value)}")
    if type_ == "int":
        if isinstance(value, int):
            return value
        if isinstance(value, float) and value.is_integer():
            return int(value)
        if isinstance(value, str) and _INT.match(value.strip()):
            return int(value)
        raise ValueError(f"expected an int, got {_shown(value)}")
    if isinstance(value, (int, float)):  # float
        return float(value)
    try:
        return float(value)
    except (TypeError, ValueError):
        raise ValueError(f"expected a float, got {_shown(value)}") from None


def _shown(value: Any) -> str:
    if isinstance(value, bool):
        return f"boolean {str(value).lower()}"
    if isinstance(value, str):
        return f"'{value}'"
    if isinstance(value, list):
        return "a list"
    if isinstance(value, dict):
        return "a mapping"
    return "null" if value is None else str(value)


@dataclass(frozen=True)
class EntryRef:
    """An entry as a binding names it.

    Attributes:
        name: The entry's name (for ``{=}``: the port's name).
        root: Whether it names the root scope (``{@name}``).
    """

    name: str
    root: bool = False

    def __str__(self) -> str:
        return f"{{{'@' if self.root else ''}{self.name}}}"


def entry_ref(value: Any, port: str = "") -> EntryRef | None:
    """Parse ``{name}``, ``{@name}`` or ``{=}``; None when ``value`` is not written so.

    Args:
        value: A binding as written.
        port: The port's name, for ``{=}``.

    Returns:
        The entry, or None for a literal. A malformed name still parses (check it with
        :data:`ENTRY_NAME`), so ``{a.b}`` is reported as a bad name, not as a literal.
    """
    if not isinstance(value, str) or not value.startswith("{"):
        return None
    match = ENTRY_REF.match(value)
    if match is None:
        return None
    name = match.group("name")
    if name == "=":
        return EntryRef(port, bool(match.group("root")))
    return EntryRef(name, bool(match.group("root")))


@dataclass(frozen=True)
class Port:
    """Declaration of one port.

    Attributes:
        name: The key in the tree file.
        type: The type name (see :func:`type_name`; a Python type is accepted and named).
        default: A literal or ``"{key}"`` used when the tree does not bind the port;
            :data:`NO_DEFAULT` when none (an input without one must be bound).
        description: One line for docs, schema and editor hover text.
        direction: Input, output or both.
        naming: How its text is read (:class:`Naming`): a value (leaves' ports) or the
            name of an entry (some of BT.CPP's own nodes).
        optional: An input without a default that the tree may leave unbound: the leaf
            reads it as BT.CPP's ``getInput`` is read, and does without when it is not
            there (Nav2's ``server_timeout``, ``server_name``).
    """

    name: str
    type: Any = "any"
    default: Any = NO_DEFAULT
    description: str = ""
    direction: Direction = Direction.INPUT
    naming: Naming = Naming.VALUE
    optional: bool = False

    def __post_init__(self) -> None:
        object.__setattr__(self, "type", type_name(self.type))
        if not ENTRY_NAME.match(self.name):
            raise TypeError(f"port name {self.name!r} is not a valid entry name")
        if self.default is NO_DEFAULT:
            return
        ref = entry_ref(self.default, self.name)
        if ref is not None:
            if not ENTRY_NAME.match(ref.name):
                raise TypeError(f"port {self.name!r}: bad default entry {self.default!r}")
        elif self.direction is not Direction.INPUT:
            raise TypeError(f"port {self.name!r}: an output's default must be an entry")
        else:
            try:
                object.__setattr__(self, "default", convert(self.type, self.default))
            except ValueError as exc:
                raise TypeError(f"port {self.name!r}: default {exc}") from None

    @property
    def required(self) -> bool:
        """Whether the tree must bind it (an input or inout port with no default, not optional)."""
        return (self.default is NO_DEFAULT and not self.optional
                and self.direction is not Direction.OUTPUT)


def InputPort(  # noqa: N802 - named like BT.CPP's InputPort<T>()
    name: str, type: type | str = "any", default: Any = NO_DEFAULT, description: str = "",
    *, optional: bool = False,
) -> Port:
    """Declare a port the leaf reads.

    Args:
        name: The key in the tree file.
        type: The type (see :func:`type_name`).
        default: A literal or ``"{key}"`` when the tree does not bind it.
        description: One line for docs and editors.
        optional: Without a default, the tree may still leave it unbound (the leaf's
            ``ports.get`` then raises KeyError, and ``name in ports`` is False).
    """
    return Port(name, type, default, description, Direction.INPUT, optional=optional)


def OutputPort(  # noqa: N802 - named like BT.CPP's OutputPort<T>()
    name: str, type: type | str = "any", default: Any = NO_DEFAULT, description: str = ""
) -> Port:
    """Declare a port the leaf writes (unbound and without default: writes are dropped)."""
    return Port(name, type, default, description, Direction.OUTPUT)


def BidirectionalPort(  # noqa: N802 - named like BT.CPP's BidirectionalPort<T>()
    name: str, type: type | str = "any", default: Any = NO_DEFAULT, description: str = ""
) -> Port:
    """Declare a port the leaf reads and writes."""
    return Port(name, type, default, description, Direction.INOUT)


@dataclass(frozen=True)
class PortBinding:
    """A leaf port's binding, resolved by validation.

    Attributes:
        port: The declaration.
        key: The absolute blackboard key, when bound to an entry.
        value: The literal (converted to the port's type), when bound to one;
            :data:`NO_DEFAULT` when the port is bound to nothing.
    """

    port: Port
    key: str | None = None
    value: Any = NO_DEFAULT
