"""Ports a control reads from blackboard entries when BT.CPP reads them (``getInput``).

Timeout's ``msec``, Repeat's ``num_cycles``, a Parallel's thresholds... may be bound to
an entry (``msec: "{t}"``). BT.CPP reads such a port either on every tick or only when
the node starts (is not RUNNING). A node that can read ports derives from
:class:`ReadsPorts`: its builder gives it a :class:`PortReader`, and the node applies
each value read in :meth:`ReadsPorts.read_port` before the tick's work.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from typing import Any

from py_trees.common import Status

from sar_framework.engine.variables import Variables


class PortReader:
    """Read a node's ports from their entries, converted to the ports' types.

    Args:
        name: The node's name (for errors).
        variables: The ports' entries, each a variable named like its port.
        types: Each port's type (``"int"`` or ``"bool"``).
        each_tick: Read on every tick (true) or only when the node starts (false).
        defaults: Values used for ports whose entry has no value (BT.CPP ignores the
            failed ``getInput`` there); a port missing here stops the tick instead.
    """

    def __init__(self, name: str, variables: Variables, types: Mapping[str, str],
                 each_tick: bool, defaults: Mapping[str, Any] | None = None) -> None:
        self.name = name
        self.variables = variables
        self.types = dict(types)
        self.each_tick = each_tick
        self.defaults = dict(defaults or {})

    def due(self, bt_status: Status) -> bool:
        """Whether BT.CPP reads the ports on a tick starting at ``bt_status``."""
        return self.each_tick or bt_status != Status.RUNNING

    def values(self) -> Iterator[tuple[str, Any]]:
        """Each port with its entry's value.

        Raises:
            RuntimeError: An entry has no value (and no default), or a value of the
                wrong type (BT.CPP: missing parameter, conversion error).
        """
        for port, type_ in self.types.items():
            yield port, self._value(port, type_)

    def _value(self, port: str, type_: str) -> Any:
        try:
            value = self.variables.get(port)
        except KeyError:
            if port in self.defaults:
                return self.defaults[port]
            raise RuntimeError(f"{self.name}: port '{port}' reads an entry that has no "
                               "value (BT.CPP: missing parameter)") from None
        if type_ == "int" and isinstance(value, float) and value.is_integer():
            value = int(value)  # BT.CPP's scripts' numbers convert alike
        if type_ == "bool" and isinstance(value, bool):
            return value
        if type_ == "int" and isinstance(value, int) and not isinstance(value, bool):
            return value
        raise RuntimeError(f"{self.name}: port '{port}' must be of type {type_}, got "
                           f"{value!r}")


class ReadsPorts:
    """A node whose ports may be read from entries (mixed into a py_trees behaviour)."""

    #: Reads the ports bound to entries; None when every port is a literal.
    port_reader: PortReader | None = None
    bt_status: Status

    def read_port(self, port: str, value: Any) -> None:
        """Take ``value``, just read for ``port``, as the node's setting."""
        raise NotImplementedError

    def read_ports(self) -> None:
        """Read the bound ports now if BT.CPP reads them on this tick."""
        reader = self.port_reader
        if reader is not None and reader.due(self.bt_status):
            for port, value in reader.values():
                self.read_port(port, value)
