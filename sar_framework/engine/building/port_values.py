"""A leaf's ports at run time: literals and blackboard entries behind one ``get``/``set``.

The builder gives a leaf that declares ports a :class:`PortValues` as its ``ports``
keyword argument. ``get(name)`` returns the literal the tree file gave (converted to the
port's type at validation) or the value of the entry the port is bound to; ``set(name,
value)`` writes an output's entry. Entries are read and written through a
:class:`~.variables.BlackboardVariables` (py_trees' own blackboard, its access control
and activity stream), one client per leaf, made once when the tree is built.

While py_trees' activity stream is off (its default), a read or write goes straight to
``Blackboard.storage`` under the key the client registered: exactly what the client
does then, once its access checks have passed, and those are settled when the client is
made (a port reads what it may read, ``set`` writes only outputs). With the stream on,
every access goes through the client, so py_trees records it.

A message literal (:class:`~.message_literals.MessageLiteral`, from the file or in an
entry) is plain data here; a leaf that can make messages (the toolkit's ROS leaves) sets
:meth:`PortValues.read_messages_with`, and ``get`` then returns the message.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

from py_trees.blackboard import Blackboard

from sar_framework.engine.message_literals import MessageLiteral
from sar_framework.engine.ports import NO_DEFAULT, PortBinding, convert
from sar_framework.engine.variables import BlackboardVariables, count_write

_CONVERTED = frozenset({"int", "float", "bool", "list"})


class PortValues:
    """One leaf's ports.

    Args:
        owner: The behaviour's name (py_trees' blackboard tools show it).
        bindings: Every declared port's resolved binding, by name.
    """

    __slots__ = ("bindings", "build_message", "keys", "literals", "owner", "variables")

    def __init__(self, owner: str, bindings: Mapping[str, PortBinding]) -> None:
        self.owner = owner
        self.bindings = dict(bindings)
        self.keys = {n: b.key for n, b in bindings.items() if b.key is not None}
        self.literals = {n: b.value for n, b in bindings.items()
                         if b.key is None and b.value is not NO_DEFAULT}
        writable = [n for n in self.keys if bindings[n].port.direction.writes]
        self.variables = BlackboardVariables(owner, self.keys, writable) if self.keys else None
        self.build_message: Callable[[MessageLiteral], Any] | None = None

    def read_messages_with(self, build: Callable[[MessageLiteral], Any]) -> None:
        """Have ``get`` return ``build(literal)`` for a message literal (once per read)."""
        self.build_message = build

    def get(self, name: str) -> Any:
        """Return the port's literal or its entry's value.

        A string found in an entry read by an ``int``, ``float``, ``bool`` or ``list``
        port is converted as a literal would be (BT.CPP does the same). A message literal
        is built by :meth:`read_messages_with`'s function, when one is set.

        Raises:
            KeyError: The port is unknown, bound to nothing, or its entry has no value.
        """
        literals = self.literals
        if name in literals:
            value = literals[name]
            if type(value) is MessageLiteral and self.build_message is not None:
                return self.build_message(value)
            return value
        key = self.keys.get(name)
        if key is None:
            what = "is not bound" if name in self.bindings else "is not a port of this leaf"
            raise KeyError(f"port '{name}' {what}")
        try:
            if Blackboard.activity_stream is None:
                value = Blackboard.storage[key]
            else:
                value = self.variables.get(name)  # type: ignore[union-attr]
        except KeyError:
            raise KeyError(f"port '{name}' of {self.owner}: entry '{key}' has no value") from None
        if type(value) is str:
            type_ = self.bindings[name].port.type
            if type_ in _CONVERTED:
                return convert(type_, value)
        elif type(value) is MessageLiteral and self.build_message is not None:
            return self.build_message(value)
        return value

    def set(self, name: str, value: Any) -> None:
        """Write an output (or inout) port's entry; an unbound output drops the value.

        Raises:
            KeyError: ``name`` is not an output of this leaf.
        """
        binding = self.bindings.get(name)
        if binding is None or not binding.port.direction.writes:
            raise KeyError(f"'{name}' is not an output port of this leaf")
        key = self.keys.get(name)
        if key is None:
            return
        if Blackboard.activity_stream is None:
            Blackboard.storage[key] = value
            count_write(key)
        else:
            self.variables.set(name, value)  # type: ignore[union-attr]

    def key(self, name: str) -> str | None:
        """Return the absolute key the port is bound to (None for a literal or nothing)."""
        return self.keys.get(name)

    def __contains__(self, name: str) -> bool:
        """Whether ``get(name)`` has a value now."""
        if name in self.literals:
            return True
        return self.variables is not None and name in self.keys and name in self.variables


def write_initial(values: Mapping[str, Any]) -> None:
    """Write entries' initial values (absolute key -> value) to py_trees' blackboard."""
    if values:
        writer = BlackboardVariables("initial values", {k: k for k in values}, values)
        for key, value in values.items():
            writer.set(key, value)
