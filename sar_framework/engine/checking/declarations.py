"""What the semantic walk knows of a node kind or plugin: one :class:`Declaration` each.

A node kind (:mod:`.node_kinds`, :mod:`.control_kinds`) and a leaf plugin
(:mod:`.plugin`) are read into the same form: their attributes, the defaults filled in
when a tree leaves an attribute out, the reference params and the blackboard ports.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from sar_framework.engine.nodes.kind_model import Attr, AttrType
from sar_framework.engine.nodes.node_kinds import KINDS, leaf_attrs
from sar_framework.engine.param import Param
from sar_framework.engine.ports import Port
from sar_framework.engine.registry import Registry
from sar_framework.engine.spec import Category


@dataclass(frozen=True)
class Declaration:
    """What the walk needs to know of one node kind or plugin.

    Attributes:
        key: The kind's key or the plugin's name.
        category: Composite, decorator or leaf.
        default_name: The ``name`` when the tree gives none.
        attrs: Every attribute.
        defaults: The values of the attributes a tree may leave out (ports excluded).
        ref_params: A plugin's reference params.
        ports: Its blackboard ports (a plugin's, or those of a BT.CPP node kind).
        symbol: A composite's text symbol in diagrams (see :class:`~.kind_model.NodeKind`).
    """

    key: str
    category: Category
    default_name: str
    attrs: tuple[Attr, ...]
    defaults: dict[str, Any]
    ref_params: tuple[Param, ...] = ()
    ports: tuple[Port, ...] = ()
    symbol: str = ""


def _defaults(attrs: tuple[Attr, ...], skipped: tuple[str, ...]) -> dict[str, Any]:
    return {a.name: a.default for a in attrs if not a.required and a.name not in skipped
            and a.type not in (AttrType.SCRIPT, AttrType.PORT)}


def declaration_of(key: str, registry: Registry) -> Declaration | None:
    """Return the declaration of a node kind or plugin (None when neither is known).

    Args:
        key: The key in the tree file.
        registry: The plugins.
    """
    kind = KINDS.get(key) or registry.kind(key)
    if kind is not None:
        ports = tuple(a.port for a in kind.attrs if a.port is not None)
        return Declaration(key, kind.category, kind.class_name, kind.attrs,
                           _defaults(kind.attrs, ("name", "selected")), ports=ports,
                           symbol=kind.symbol)
    plugin = registry.get(key)
    if plugin is None:
        return None
    attrs = leaf_attrs(plugin)
    refs = tuple(p for p in plugin.params if p.ref is not None)
    return Declaration(key, Category.LEAF, key, attrs, _defaults(attrs, ("name", "id")), refs,
                       plugin.ports)
