"""A node kind's builder, from what its declaration names (``NodeKind.build``).

Every kind, built-in or a plugin's, says how it is built beside its declaration; this
module only turns that into a callable ``builder(node, children, context)``, once per
kind: a ``"package.module:name"`` is imported here (declarations stay free of py_trees),
a behaviour class is called with the node's attributes and the context objects the kind
declares, and the ports the kind ``reads`` are read from their entries when BT.CPP
reads them (:func:`~.control_build.reading_ports`).
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping
from typing import Any

import py_trees

from sar_framework.engine.building.control_build import clock_of, reading_ports
from sar_framework.engine.nodes.kind_model import BuildRef, NodeKind
from sar_framework.engine.spec import Category, NodeSpec

Behaviour = py_trees.behaviour.Behaviour
KindBuilder = Callable[[NodeSpec, list[Behaviour], Mapping[str, Any]], Behaviour]

_BUILT: dict[int, tuple[NodeKind, KindBuilder]] = {}


def resolve(ref: BuildRef, key: str) -> Any:
    """The object ``ref`` names: itself, or ``name`` of ``package.module`` imported.

    Raises:
        ValueError: The kind names no builder.
        ImportError, AttributeError: ``ref`` names nothing importable.
    """
    if ref is None:
        raise ValueError(f"node kind '{key}' names no builder (its declaration's 'build')")
    if not isinstance(ref, str):
        return ref
    module, _, name = ref.partition(":")
    return getattr(importlib.import_module(module), name)


def class_builder(cls: type, context_keys: tuple[str, ...]) -> KindBuilder:
    """Build by calling ``cls`` with the node's name, children or child, and attributes.

    Args:
        cls: The behaviour class.
        context_keys: Build-context objects passed as keyword arguments (``clock``: the
            context's clock, else ``time.monotonic``).
    """

    def build(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
              ) -> Behaviour:
        extra = {key: clock_of(context) if key == "clock" else context[key]
                 for key in context_keys}
        if node.category is Category.DECORATOR:
            return cls(node.name, children[0], **node.attrs, **extra)
        if node.category is Category.COMPOSITE:
            return cls(node.name, children, **node.attrs, **extra)
        return cls(node.name, **node.attrs, **extra)

    return build


def builder_of(kind: NodeKind) -> KindBuilder:
    """The builder of ``kind`` (worked out on its first node, then kept).

    Raises:
        ValueError, ImportError, AttributeError: The declaration's ``build`` names
            nothing usable.
    """
    known = _BUILT.get(id(kind))
    if known is not None and known[0] is kind:
        return known[1]
    target = resolve(kind.build, kind.key)
    build = class_builder(target, kind.context) if isinstance(target, type) else target
    if kind.reads:
        build = reading_ports(build, kind.reads, kind.reads_each_tick,
                              kind.reads_keep_default)
    _BUILT[id(kind)] = (kind, build)
    return build
