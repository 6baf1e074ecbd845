"""Named variables on py_trees' blackboard: what ports and scripts read and write.

A tree's entries live on py_trees' own blackboard under absolute keys; the validator
resolves every name a node uses (a port bound to ``{goal}``, a script's ``door_open``)
to the absolute key of the scope it belongs to (``/goal``, ``/Recover@0.2/retries``).
A :class:`BlackboardVariables` is one node's view: its names, each remapped to its key
through a py_trees :class:`~py_trees.blackboard.Client` (``register_key(remap_to=...)``),
so py_trees' access control, activity stream and watchers see every read and write.
Works on py_trees 2.2.3 and 2.6.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any, Protocol

import py_trees
from py_trees.common import Access


class Variables(Protocol):
    """Read and write named variables (a script's or a node's ports' view)."""

    def get(self, name: str) -> Any:
        """Return the value of ``name``; raise KeyError when it has none."""

    def set(self, name: str, value: Any) -> None:
        """Give ``name`` a value."""

    def unset(self, name: str) -> None:
        """Remove ``name``'s value (no error when it has none)."""

    def __contains__(self, name: str) -> bool:
        """Whether ``name`` has a value."""


def value_or_none(variables: Variables, name: str) -> Any:
    """Return the value of ``name``, or None when it is unset (BT.CPP's failed ``getInput``).

    Args:
        variables: Where ``name`` lives.
        name: The variable's name.

    Returns:
        Its value, or None.
    """
    try:
        return variables.get(name)
    except KeyError:
        return None


#: Writes per absolute key made through any BlackboardVariables (BT.CPP's sequence id).
_WRITES: dict[str, int] = {}


def count_write(key: str) -> None:
    """Note a write of the absolute ``key`` made without a :class:`BlackboardVariables`.

    A leaf's output port writes py_trees' storage directly while the activity stream is
    off (:mod:`.port_values`); SkipUnlessUpdated and friends must still see it.
    """
    _WRITES[key] = _WRITES.get(key, 0) + 1


class BlackboardVariables:
    """A :class:`Variables` view of py_trees' blackboard through one client.

    It also counts the writes made through it per key (:meth:`version`), which
    SkipUnlessUpdated and WaitValueUpdate read; writes by other py_trees clients are
    not counted.

    Args:
        owner: Who reads and writes (the behaviour's name; shown by py_trees' tools).
        keys: Each name this view uses -> its absolute blackboard key.
        writable: The names it may write (the rest are read-only).
    """

    def __init__(
        self, owner: str, keys: Mapping[str, str], writable: Iterable[str] = ()
    ) -> None:
        self.keys = dict(keys)
        writes = set(writable)
        self.client = py_trees.blackboard.Client(name=owner)
        for name, key in self.keys.items():
            self.client.register_key(key=name, access=Access.READ, remap_to=key)
            if name in writes:
                self.client.register_key(key=name, access=Access.WRITE, remap_to=key)

    def get(self, name: str) -> Any:
        """Return the value of ``name``; raise KeyError when it has none."""
        try:
            return self.client.get(name)
        except KeyError:
            raise KeyError(name) from None

    def set(self, name: str, value: Any) -> None:
        """Give ``name`` a value (it must be writable)."""
        self.client.set(name, value, overwrite=True)
        count_write(self.keys[name])

    def unset(self, name: str) -> None:
        """Remove ``name``'s value (no error when it has none)."""
        self.client.unset(name)
        _WRITES.pop(self.keys[name], None)

    def __contains__(self, name: str) -> bool:
        """Whether ``name`` has a value."""
        return self.client.exists(name)

    def version(self, name: str) -> int:
        """How many times ``name`` was written (through any BlackboardVariables) since unset."""
        return _WRITES.get(self.keys[name], 0)
