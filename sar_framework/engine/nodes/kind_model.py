"""The shape of a node kind: its attributes, their types and the rules between them.

:mod:`.node_kinds` (py_trees' composites and decorators) and :mod:`.control_kinds`
(BT.CPP's nodes) and node-kind plugins declare their kinds with these classes; the validator, the
schema and the docs read them.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from enum import Enum
from typing import Any

from sar_framework.engine.ports import Port
from sar_framework.engine.spec import Category


class AttrType(str, Enum):
    """The value type of an attribute, as the validator and the schema see it."""

    STRING = "string"
    INTEGER = "integer"
    NUMBER = "number"
    BOOLEAN = "boolean"
    NODE = "node"
    NODES = "nodes"
    STRINGS = "strings"
    PORT = "port"
    SCRIPT = "script"


#: Python param type -> attribute type.
PARAM_ATTR_TYPES: dict[type, AttrType] = {
    str: AttrType.STRING,
    int: AttrType.INTEGER,
    float: AttrType.NUMBER,
    bool: AttrType.BOOLEAN,
}


@dataclass(frozen=True)
class Attr:
    """One attribute of a node kind (or one param of a leaf plugin).

    Attributes:
        name: The key in the tree file.
        type: The value type.
        required: Whether the key must be present.
        default: The value when absent (ignored when required).
        description: One line for docs and editor hover text.
        enum: The allowed values, when the set is closed.
        minimum: Inclusive lower bound (numbers).
        maximum: Inclusive upper bound (numbers).
        exclusive_minimum: Exclusive lower bound (numbers).
        excluded: Values forbidden even inside the range (e.g. ``0`` for ``num_success``).
        min_items: Minimum length of a list value.
        max_items: Maximum length of a list value.
        min_length: Minimum length of a string value.
        nullable: Whether ``null`` is accepted (a param defaulting to None).
        ref: For a reference param: the plugin name the referenced leaf must have.
        port: For a port (a leaf's, or a BT.CPP node's blackboard port): its declaration
            (the value binds it, see :mod:`.ports`).
    """

    name: str
    type: AttrType
    required: bool = False
    default: Any = None
    description: str = ""
    enum: tuple[Any, ...] | None = None
    minimum: float | None = None
    maximum: float | None = None
    exclusive_minimum: float | None = None
    excluded: tuple[Any, ...] = ()
    min_items: int | None = None
    max_items: int | None = None
    min_length: int | None = None
    nullable: bool = False
    ref: str | None = None
    port: Port | None = None


@dataclass(frozen=True)
class Rule:
    """A conditional attribute rule: ``attr`` depends on the value of ``if_attr``.

    When ``if_attr`` equals ``equals``, ``then`` applies to ``attr``; otherwise
    ``otherwise`` does. Each is ``"required"``, ``"forbidden"`` or None.

    Attributes:
        attr: The constrained attribute.
        if_attr: The attribute whose value decides.
        equals: The deciding value.
        then: What applies to ``attr`` when ``if_attr == equals``.
        otherwise: What applies otherwise (also when ``if_attr`` is absent).
    """

    attr: str
    if_attr: str
    equals: Any
    then: str | None = None
    otherwise: str | None = None


BuildRef = str | Callable[..., Any] | None
"""How a kind is built, named beside its declaration.

``"package.module:name"`` (imported only when a tree is built, so that declaring,
validating and generating the schema never import py_trees) or the object itself: a
builder ``build(node, children, context) -> behaviour``, or a behaviour class, called as
``cls(name, children, **attrs)`` (a control), ``cls(name, child, **attrs)`` (a decorator)
or ``cls(name, **attrs)`` (a leaf), plus the declared ``context`` objects.
"""


@dataclass(frozen=True)
class NodeKind:
    """A composite, decorator or built-in leaf kind.

    Attributes:
        key: The key in a tree file (``sequence``, ``one_shot``).
        category: Composite, decorator or (built-in) leaf.
        class_name: The py_trees class it builds (``Sequence``, ``OneShot``); also the
            default ``name``.
        description: One line for docs and the schema.
        attrs: Every attribute, ``name`` and ``child``/``children`` included.
        rules: Conditional rules between attributes.
        symbol: A composite's py_trees-style text symbol in diagrams (``{-}`` resumes at
            a running child, ``[-]`` starts from the first, ``{o}``/``[o]`` the same for a
            fallback, ``/_/`` parallel); empty: worked out from the node (``memory``).
        build: How a node of this kind is built: a :data:`BuildRef`.
        context: The build context's objects a behaviour class named by ``build`` takes
            as keyword arguments (``clock``: the tree's clock, ``time.monotonic`` when
            the context has none).
        reads: The ports BT.CPP reads with ``getInput`` (a literal, or ``{name}`` read
            from its entry when BT.CPP reads it).
        reads_each_tick: Whether ``reads`` are read on every tick, else when the node starts.
        reads_keep_default: Whether a port of ``reads`` whose entry has no value keeps its
            default (BT.CPP ignores that failed ``getInput``), rather than stopping the
            tick (BT.CPP's "Missing parameter").
        differences: Where this kind ticks unlike the kind it is exported as (a py_trees
            kind and its BT.CPP spelling): the node-kind reference and the palette show it.
        spellings: Other BT.CPP IDs an imported XML may name it by (``SequenceStar``).
        reports: What the runner reports about such a node beyond its status (see
            :mod:`sar_framework.runner.reasons`); ``"recovery"``: a control whose second
            child recovers its first, each recovery a retry (its behaviour keeps
            ``index``, ``retries`` and ``number_of_retries``).
    """

    key: str
    category: Category
    class_name: str
    description: str
    attrs: tuple[Attr, ...]
    rules: tuple[Rule, ...] = ()
    symbol: str = ""
    build: BuildRef = None
    context: tuple[str, ...] = ()
    reads: tuple[str, ...] = ()
    reads_each_tick: bool = True
    reads_keep_default: bool = False
    differences: str = ""
    spellings: tuple[str, ...] = ()
    reports: str = ""

    def attr(self, name: str) -> Attr | None:
        """Return the attribute called ``name``, or None."""
        for a in self.attrs:
            if a.name == name:
                return a
        return None

    def settings(self) -> tuple[Attr, ...]:
        """The attributes that set the node up (a palette's ports, a listing's lines).

        Not its ``name``, its children or its pre- and post-conditions (``_skipIf``...).
        """
        return tuple(a for a in self.attrs if a.name != "name" and not a.name.startswith("_")
                     and a.type not in (AttrType.NODE, AttrType.NODES))


def name_attr(default: str) -> Attr:
    """The ``name`` attribute every kind has, defaulting to ``default``."""
    return Attr("name", AttrType.STRING, default=default, description="The behaviour's name.")

#: BT.CPP's pre- and post-condition attributes, each a script; every node takes them.
CONDITION_ATTRS: tuple[Attr, ...] = tuple(
    Attr(name, AttrType.SCRIPT, min_length=1, description=f"Script: {text}")
    for name, text in (
        ("_failureIf", "if true before the node starts, FAILURE without ticking it."),
        ("_successIf", "if true before the node starts, SUCCESS without ticking it."),
        ("_skipIf", "if true before the node starts, SKIPPED without ticking it."),
        ("_while", "checked before and while the node runs: false skips it or halts it."),
        ("_onSuccess", "run when the node succeeds."),
        ("_onFailure", "run when the node fails."),
        ("_onHalted", "run when the node is halted while RUNNING."),
        ("_post", "run when the node succeeds or fails."),
    )
)
