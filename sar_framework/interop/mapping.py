"""The one table between our composites/decorators and BehaviorTree.CPP 4 nodes.

The kinds of :mod:`~sar_framework.engine.nodes.control_kinds` are BT.CPP's (and Nav2's) own
nodes: each maps 1:1 to the ID it is named after, its attributes to the ports of the same
names, both ways. Each py_trees kind (``sequence``, ``one_shot``...) maps either to a
built-in BT.CPP node that ticks its children the same way (the engine's one table,
:data:`~sar_framework.engine.nodes.py_trees_spellings.PY_TREES_SPELLINGS`; importing that
node gives the BT.CPP kind back), or, when BT.CPP has no such node, to a *custom*
node ``Sar<ClassName>`` whose ports are our attributes (declared in ``<TreeNodesModel>``,
so Groot2 can show and edit it; a BT.CPP program must register it to run the tree).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from sar_framework.engine.message_literals import MessageLiteral, message_text
from sar_framework.engine.nodes.control_kinds import CONTROL_KINDS
from sar_framework.engine.nodes.kind_model import Attr
from sar_framework.engine.nodes.node_kinds import PY_TREES_KINDS, SCRIPT_KINDS, AttrType, NodeKind
from sar_framework.engine.nodes.py_trees_spellings import PY_TREES_SPELLINGS
from sar_framework.engine.registry import Registry

#: Prefix of the custom BT.CPP node a kind without a built-in equivalent becomes.
CUSTOM_PREFIX = "Sar"


@dataclass(frozen=True)
class Builtin:
    """A BT.CPP built-in node equivalent to one of our kinds with some attribute values.

    Attributes:
        btcpp_id: The BT.CPP registration ID (the XML tag).
        kind: Our node kind.
        fixed: Our attributes this mapping requires (e.g. ``memory: true``).
        to_ports: Our attributes -> the BT.CPP ports to write.
        from_ports: BT.CPP ports (strings) -> our attributes, on import (only the 1:1
            mappings are imported); raises ValueError on a value it cannot express.
    """

    btcpp_id: str
    kind: str
    fixed: tuple[tuple[str, Any], ...] = ()
    to_ports: Callable[[dict[str, Any]], dict[str, str]] = lambda attrs: {}
    from_ports: Callable[[dict[str, str]], dict[str, Any]] = lambda ports: {}


def port_text(value: Any) -> str:
    """Format an attribute value as BT.CPP reads it from an XML attribute."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (list, tuple)):
        return ";".join(str(v) for v in value)
    if isinstance(value, MessageLiteral):
        return message_text(value)
    return str(value)


def _port_value(attr_type: AttrType, name: str, text: str) -> Any:
    try:
        if attr_type is AttrType.BOOLEAN:
            lowered = text.strip().lower()
            if lowered not in ("true", "false"):
                raise ValueError
            return lowered == "true"
        if attr_type is AttrType.INTEGER:
            return int(text)
        if attr_type is AttrType.NUMBER:
            return float(text)
    except ValueError:
        raise ValueError(f"'{name}' must be a {attr_type.value}, got '{text}'") from None
    return text


def attr_value(attr_type: AttrType, name: str, text: str) -> Any:
    """Convert an imported attribute to our type: integral numbers stay ints, lists split.

    Raises:
        ValueError: ``'name' must be a <type>, got '<text>'``.
    """
    if attr_type is AttrType.NUMBER:
        value = _port_value(attr_type, name, text)
        return int(value) if value.is_integer() and "." not in text else value
    if attr_type is AttrType.STRINGS:
        return [part for part in text.split(";") if part]
    return _port_value(attr_type, name, text)


def _typed_port_value(attr: Attr, text: str) -> Any:
    """An imported attribute; an int or bool port's literal converted (``msec: 450``)."""
    typed = {"int": AttrType.INTEGER, "bool": AttrType.BOOLEAN}
    if attr.port is not None and attr.port.type in typed and not text.strip().startswith("{"):
        return _port_value(typed[attr.port.type], attr.name, text)
    return _port_value(attr.type, attr.name, text)


def same_ids(kind: NodeKind, btcpp_id: str | None = None) -> Builtin:
    """The 1:1 mapping of a BT.CPP/Nav2 kind: every attribute is the port of its name."""
    names = kind.settings()  # the conditions are btcpp_scripts'

    def to_ports(attrs: dict[str, Any]) -> dict[str, str]:
        return {a.name: port_text(attrs[a.name]) for a in names
                if attrs.get(a.name) is not None}

    def from_ports(ports: dict[str, str]) -> dict[str, Any]:
        known = {a.name for a in names}
        extra = sorted(set(ports) - known - {"name"})
        if extra:
            own = sorted(k for k in known if not k.startswith("_"))  # not _skipIf...
            raise ValueError(f"no port {', '.join(repr(e) for e in extra)} (its ports: "
                             f"{', '.join(own) or 'none'})")
        missing = [a.name for a in names if a.required and a.name not in ports]
        if missing:
            raise ValueError(f"needs the port '{missing[0]}'")
        return {a.name: _typed_port_value(a, ports[a.name]) for a in names if a.name in ports}

    return Builtin(btcpp_id or kind.key, kind.key, to_ports=to_ports, from_ports=from_ports)


BUILTIN: tuple[Builtin, ...] = (
    *(Builtin(s.btcpp_id, s.kind, s.fixed, s.to_ports) for s in PY_TREES_SPELLINGS),
    *(same_ids(kind) for kind in CONTROL_KINDS),
    *(same_ids(kind) for kind in SCRIPT_KINDS),
    *(same_ids(kind, spelling) for kind in CONTROL_KINDS for spelling in kind.spellings),
)

#: BT.CPP ID -> its mapping; an ID shared with a py_trees kind imports as the BT.CPP kind.
BUILTIN_BY_ID: dict[str, Builtin] = {b.btcpp_id: b for b in BUILTIN}

#: BT.CPP (and Nav2) nodes that are refused on import, with the reason and a way out.
REFUSED: dict[str, str] = {
}


def plugin_mapping(tag: str, registry: Registry) -> Builtin | None:
    """The mapping of a plugin's control or decorator named ``tag`` (or spelt so), or None."""
    for spec in registry.kind_plugins():
        if tag == spec.name or tag in spec.kind.spellings:
            return same_ids(spec.kind, tag)
    return None


def builtin_for(kind: str, attrs: dict[str, Any]) -> Builtin | None:
    """Return the built-in BT.CPP node for one of our nodes, or None when there is none."""
    for entry in BUILTIN:
        if entry.kind == kind and all(attrs.get(k) == v for k, v in entry.fixed):
            return entry
    return None


def custom_id(kind: NodeKind) -> str:
    """The BT.CPP ID of the custom node a kind becomes (``SarOneShot``)."""
    return CUSTOM_PREFIX + kind.class_name


def always_builtin(kind: NodeKind) -> bool:
    """Whether every node of ``kind`` exports as a BT.CPP built-in (never as ``Sar...``).

    True when a mapping takes the kind whatever its attributes, or when the mappings'
    fixed values cover every value of the one attribute they fix (``memory``).
    """
    entries = [b for b in BUILTIN if b.kind == kind.key]
    if any(not b.fixed for b in entries):
        return True
    fixed = {name for b in entries for name, _ in b.fixed}
    if len(fixed) != 1 or any(len(b.fixed) != 1 for b in entries):
        return False
    attr = kind.attr(fixed.pop())
    values = (True, False) if attr is not None and attr.type is AttrType.BOOLEAN else (
        attr.enum if attr is not None else None)
    return values is not None and set(values) <= {b.fixed[0][1] for b in entries}


#: Custom BT.CPP ID -> our kind.
CUSTOM_KINDS: dict[str, NodeKind] = {custom_id(k): k for k in PY_TREES_KINDS.values()}


def custom_ports(kind: NodeKind) -> list[tuple[str, str, Any, str]]:
    """The ports of a kind's custom node: ``(name, C++ type, default, description)``."""
    types = {AttrType.STRING: "std::string", AttrType.INTEGER: "int",
             AttrType.NUMBER: "double", AttrType.BOOLEAN: "bool",
             AttrType.STRINGS: "std::string"}
    return [(a.name, types[a.type], None if a.required else a.default, a.description)
            for a in kind.attrs if a.type in types and a.name != "name"]
