"""Control and decorator plugins: a behaviour plus the declaration BT.CPP's kinds use.

A plugin adds a control or decorator node kind by marking its behaviour class with
:func:`node_kind` and the same :class:`~.nodes.kind_model.NodeKind` the engine declares
BT.CPP's nodes with (:func:`control_kind`, :func:`decorator_kind`: the key, one line of
docs, its ports and params as attributes, its children's arity)::

    @node_kind(decorator_kind("Twice", "Tick the child to two successes."))
    class Twice(py_trees.decorators.Decorator):
        def __init__(self, name, child): ...

The registry finds it as it finds leaves (entry points, a tree's ``plugins:``); the schema,
validation, build and listings then take it as a built-in kind. The declaration says how
its nodes are built, as a built-in kind's does (``NodeKind.build``): without a ``build``,
the class is called as ``cls(name, children, **attrs)`` (a control) or ``cls(name, child,
**attrs)`` (a decorator), plus the declared ``context`` objects (``context=("clock",)``);
a ``build(node, children, context)`` gets the validated node, the built children and the
tree's context (the clock, the robot's state), as leaves do. The ports a kind declares it
``reads`` are read from their entries when BT.CPP reads them.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, TypeVar

from sar_framework.engine.nodes.control_kinds import children_attr, control_kind, decorator_kind
from sar_framework.engine.nodes.kind_model import NodeKind
from sar_framework.engine.spec import Category, NodeSpec

__all__ = ["KIND_ATTRIBUTE", "KindBuilder", "KindSpec", "children_attr", "control_kind",
           "declared_kind", "decorator_kind", "node_kind"]

#: The attribute :func:`node_kind` sets on a class; discovery looks for it.
KIND_ATTRIBUTE = "__sar_node_kind__"

KindBuilder = Callable[[NodeSpec, list[Any], Mapping[str, Any]], Any]
"""``build(node, children, context)`` -> the behaviour of one node."""


@dataclass(frozen=True)
class KindSpec:
    """Everything the engine knows about one control or decorator plugin.

    Attributes:
        kind: Its declaration (key, category, attributes, one line of docs, its builder,
            the other IDs an imported XML may name it by).
        cls: The behaviour class.
        source: Where it was found; set by the registry.
    """

    kind: NodeKind
    cls: type
    source: str = field(default="", compare=False)

    @property
    def name(self) -> str:
        """The node kind in a tree file."""
        return self.kind.key


_T = TypeVar("_T", bound=type)


def node_kind(kind: NodeKind, *, build: KindBuilder | None = None,
              spellings: Sequence[str] = ()) -> Callable[[_T], _T]:
    """Mark a behaviour class as the plugin of a control or decorator kind.

    Args:
        kind: Its declaration (:func:`control_kind` or :func:`decorator_kind`).
        build: ``build(node, children, context)``; default: the class with the attributes.
        spellings: Other BT.CPP IDs an imported XML may name it by.

    Returns:
        A class decorator that records a :class:`KindSpec` on the class and returns it
        (its kind's ``build``: ``build``, else one the declaration named, else the class;
        ``spellings`` are added to the kind's).

    Raises:
        TypeError: When ``kind`` is not a control or a decorator.
    """

    def mark(cls: _T) -> _T:
        if kind.category not in (Category.COMPOSITE, Category.DECORATOR):
            raise TypeError(f"{cls.__name__}: a node kind plugin is a control or a decorator; "
                            "a leaf is declared with @leaf")
        built = dataclasses.replace(kind, build=build or kind.build or cls,
                                    spellings=(*kind.spellings, *spellings))
        setattr(cls, KIND_ATTRIBUTE, KindSpec(built, cls))
        return cls

    return mark


def declared_kind(behaviour: object) -> NodeKind | None:
    """The declaration of a plugin's control or decorator ``behaviour`` is, or None."""
    spec = getattr(behaviour, KIND_ATTRIBUTE, None)
    return spec.kind if isinstance(spec, KindSpec) else None
