"""The node kinds a tree file may use besides plugins: composites and decorators.

One declarative table drives the fast validator (:mod:`.validate`), the JSON
Schema (:mod:`.schema`), the builder (:mod:`.build`) and the docs. A leaf
plugin's params are turned into the same :class:`Attr` form by
:func:`leaf_attrs`, so every node is checked by one code path.

Supported decorators are those py_trees offers in both 2.2.3 and 2.6.0 whose
arguments a tree file can express: ``EternalGuard`` (needs a Python callable),
``StatusToBlackboard`` and ``ForEach`` (blackboard based; ``ForEach`` is 2.6
only) are left out on purpose: this framework shares state by references.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum
from typing import Any

from sar_framework.engine.plugin import REQUIRED, PluginSpec
from sar_framework.engine.ports import Port
from sar_framework.engine.spec import Category

#: The node kind that inserts a named subtree (``subtree: NAME``).
SUBTREE = "subtree"
#: The tree format version this engine reads.
FORMAT_VERSION = 1
#: Deepest nesting of nodes accepted (keeps every recursive pass far from Python's limit).
MAX_DEPTH = 200


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


#: Python param type -> attribute type.
_PARAM_ATTR_TYPES: dict[type, AttrType] = {
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
        min_length: Minimum length of a string value.
        nullable: Whether ``null`` is accepted (a param defaulting to None).
        ref: For a reference param: the plugin name the referenced leaf must have.
        port: For a leaf's port: its declaration (the value binds it, see :mod:`.ports`).
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


@dataclass(frozen=True)
class NodeKind:
    """A composite or decorator kind.

    Attributes:
        key: The key in a tree file (``sequence``, ``one_shot``).
        category: Composite or decorator.
        class_name: The py_trees class it builds (``Sequence``, ``OneShot``); also the
            default ``name``.
        description: One line for docs and the schema.
        attrs: Every attribute, ``name`` and ``child``/``children`` included.
        rules: Conditional rules between attributes.
    """

    key: str
    category: Category
    class_name: str
    description: str
    attrs: tuple[Attr, ...]
    rules: tuple[Rule, ...] = ()

    def attr(self, name: str) -> Attr | None:
        """Return the attribute called ``name``, or None."""
        for a in self.attrs:
            if a.name == name:
                return a
        return None


def _name_attr(default: str) -> Attr:
    return Attr("name", AttrType.STRING, default=default, description="The behaviour's name.")


_CHILDREN = Attr(
    "children", AttrType.NODES, required=True, min_items=1, description="The child nodes, in order."
)
_CHILD = Attr("child", AttrType.NODE, required=True, description="The decorated node.")
_MEMORY = Attr(
    "memory",
    AttrType.BOOLEAN,
    required=True,
    description="true: resume at the running child; false: re-evaluate from the first child "
    "every tick.",
)


def _composite(
    key: str, class_name: str, description: str, *extra: Attr, rules: tuple[Rule, ...] = ()
) -> NodeKind:
    return NodeKind(
        key,
        Category.COMPOSITE,
        class_name,
        description,
        (_name_attr(class_name), *extra, _CHILDREN),
        rules,
    )


def _decorator(
    key: str, class_name: str, description: str, *extra: Attr, rules: tuple[Rule, ...] = ()
) -> NodeKind:
    return NodeKind(
        key,
        Category.DECORATOR,
        class_name,
        description,
        (_name_attr(class_name), *extra, _CHILD),
        rules,
    )


_PARALLEL_POLICIES = ("success_on_all", "success_on_one", "success_on_selected")
_STATUSES = ("success", "failure", "running")

_KIND_LIST: tuple[NodeKind, ...] = (
    _composite(
        "sequence", "Sequence", "Tick children in order until one does not succeed.", _MEMORY
    ),
    _composite(
        "selector", "Selector", "Tick children in order until one does not fail.", _MEMORY
    ),
    _composite(
        "parallel",
        "Parallel",
        "Tick every child each tick; the policy decides success.",
        Attr(
            "policy",
            AttrType.STRING,
            required=True,
            enum=_PARALLEL_POLICIES,
            description="When the parallel succeeds: all children, one child, or the "
            "children named in 'selected'.",
        ),
        Attr(
            "synchronise",
            AttrType.BOOLEAN,
            default=True,
            description="Stop ticking children that already succeeded "
            "(success_on_all, success_on_selected).",
        ),
        Attr(
            "selected",
            AttrType.STRINGS,
            min_items=1,
            description="Names of the children that must succeed (success_on_selected only).",
        ),
        rules=(
            Rule(
                "selected", "policy", "success_on_selected", then="required", otherwise="forbidden"
            ),
            Rule("synchronise", "policy", "success_on_one", then="forbidden"),
        ),
    ),
    _decorator(
        "one_shot",
        "OneShot",
        "Run the child until it completes once, then keep returning that result.",
        Attr(
            "policy",
            AttrType.STRING,
            required=True,
            enum=("on_completion", "on_successful_completion"),
            description="Latch on any completion, or only on success.",
        ),
    ),
    _decorator("inverter", "Inverter", "Swap SUCCESS and FAILURE."),
    _decorator(
        "retry",
        "Retry",
        "Re-run a failing child up to num_failures times.",
        Attr(
            "num_failures",
            AttrType.INTEGER,
            required=True,
            minimum=1,
            description="Failures allowed before the decorator fails.",
        ),
    ),
    _decorator(
        "repeat",
        "Repeat",
        "Re-run a succeeding child until it has succeeded num_success times.",
        Attr(
            "num_success",
            AttrType.INTEGER,
            required=True,
            minimum=-1,
            excluded=(0,),
            description="Successes needed; -1 repeats forever.",
        ),
    ),
    _decorator(
        "timeout",
        "Timeout",
        "Fail the child if it is still RUNNING after duration seconds.",
        Attr(
            "duration",
            AttrType.NUMBER,
            required=True,
            exclusive_minimum=0.0,
            description="Seconds before the child is stopped and the decorator fails.",
        ),
    ),
    _decorator(
        "condition",
        "Condition",
        "Return RUNNING until the child returns status, then SUCCESS.",
        Attr(
            "status",
            AttrType.STRING,
            required=True,
            enum=_STATUSES,
            description="The child status to wait for.",
        ),
    ),
    _decorator("count", "Count", "Pass the child's status through and count ticks by status."),
    _decorator("pass_through", "PassThrough", "Return the child's status unchanged."),
    _decorator("failure_is_success", "FailureIsSuccess", "FAILURE becomes SUCCESS."),
    _decorator("failure_is_running", "FailureIsRunning", "FAILURE becomes RUNNING."),
    _decorator("success_is_failure", "SuccessIsFailure", "SUCCESS becomes FAILURE."),
    _decorator("success_is_running", "SuccessIsRunning", "SUCCESS becomes RUNNING."),
    _decorator("running_is_failure", "RunningIsFailure", "RUNNING becomes FAILURE."),
    _decorator("running_is_success", "RunningIsSuccess", "RUNNING becomes SUCCESS."),
)

#: Composite and decorator kinds by key.
KINDS: dict[str, NodeKind] = {k.key: k for k in _KIND_LIST}

#: Keys no plugin may take: they already mean something in a tree file.
RESERVED_KINDS: frozenset[str] = frozenset({*KINDS, SUBTREE})

#: py_trees decorators deliberately not offered, with the reason (for docs and messages).
UNSUPPORTED_DECORATORS: dict[str, str] = {
    "eternal_guard": "needs a Python callable; use a selector with a condition leaf",
    "status_to_blackboard": "writes the blackboard; this framework shares state by references",
    "for_each": "py_trees 2.6 only and blackboard based",
}


def leaf_attrs(plugin: PluginSpec) -> tuple[Attr, ...]:
    """Return a leaf plugin's attributes: ``name``, ``id``, its params, then its ports.

    Args:
        plugin: The plugin declaration.

    Returns:
        The attributes in the order the docs list them.
    """
    attrs = [
        _name_attr(plugin.name),
        Attr(
            "id",
            AttrType.STRING,
            min_length=1,
            description="Unique id, for references from other leaves.",
        ),
    ]
    for p in plugin.params:
        required = p.default is REQUIRED
        attrs.append(
            Attr(
                p.name,
                AttrType.STRING if p.ref is not None else _PARAM_ATTR_TYPES[p.type],
                required=required,
                default=None if required else p.default,
                description=p.description,
                enum=tuple(p.enum) if p.enum is not None else None,
                minimum=p.minimum,
                maximum=p.maximum,
                exclusive_minimum=p.exclusive_minimum,
                min_length=1 if p.ref is not None else None,
                nullable=not required and p.default is None,
                ref=p.ref,
            )
        )
    for port in plugin.ports:
        attrs.append(Attr(port.name, AttrType.PORT, required=port.required,
                          description=port.description, port=port))
    return tuple(attrs)


#: Top-level keys of a tree file, in the order the docs list them.
TOP_LEVEL_ATTRS: tuple[Attr, ...] = (
    Attr("format", AttrType.INTEGER, required=True, enum=(FORMAT_VERSION,),
         description="The tree format version; always 1."),
    Attr("name", AttrType.STRING, description="The tree's name (default: the file name)."),
    Attr("description", AttrType.STRING, description="Free text."),
    Attr("plugins", AttrType.STRINGS,
         description="Extra plugin modules, .py files or directories, relative to this file."),
    Attr("include", AttrType.STRINGS,
         description="Tree files whose subtrees become available here, relative to this file."),
    Attr("blackboard", AttrType.NODE,
         description="The main tree's blackboard entries: name -> {type, initial, description}."),
    Attr("subtrees", AttrType.NODE, description="Named fragments, inserted with {subtree: NAME}."),
    Attr("root", AttrType.NODE, description="The root node (required in the file you load)."),
)  # fmt: skip
#: The top-level attributes by key.
TOP_LEVEL = {a.name: a for a in TOP_LEVEL_ATTRS}
