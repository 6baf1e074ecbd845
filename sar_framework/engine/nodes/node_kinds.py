"""The node kinds a tree file may use besides plugins: composites and decorators.

One declarative table drives the fast validator (:mod:`.validate`), the JSON
Schema (:mod:`.schema`), the builder (each kind names its own: py_trees' class or a
converting builder of :mod:`~..building.py_trees_build`), the docs and the palette (a
kind's ``differences`` from the BT.CPP node it is exported as). A leaf
plugin's params are turned into the same :class:`Attr` form by
:func:`leaf_attrs`, so every node is checked by one code path.

Supported decorators are those py_trees offers in both 2.2.3 and 2.6.0 whose
arguments a tree file can express: ``EternalGuard`` (needs a Python callable),
``StatusToBlackboard`` and ``ForEach`` (blackboard based; ``ForEach`` is 2.6
only) are left out on purpose: this framework shares state by references.
"""

from __future__ import annotations

from collections.abc import Callable

from sar_framework.engine.nodes.control_kinds import CONTROL_KINDS
from sar_framework.engine.nodes.kind_model import (
    CONDITION_ATTRS,
    PARAM_ATTR_TYPES,
    Attr,
    AttrType,
    NodeKind,
    Rule,
    name_attr,
)
from sar_framework.engine.plugin import REQUIRED, PluginSpec
from sar_framework.engine.spec import Category

#: The node kind that inserts a named subtree (``subtree: NAME``).
SUBTREE = "subtree"
#: The tree format version this engine reads.
FORMAT_VERSION = 1
#: Deepest nesting of nodes accepted (keeps every recursive pass far from Python's limit).
MAX_DEPTH = 200


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




#: Where py_trees' classes and the builders that convert attributes for them are.
_PY_TREES = "py_trees.decorators:"
_CONVERT = "sar_framework.engine.building.py_trees_build:"


def _maker(category: Category, children: Attr) -> Callable[..., NodeKind]:
    """Make kinds of ``category`` whose children are given by the attribute ``children``.

    The maker takes the kind's key, py_trees class name, description, its own attributes,
    its rules (keyword ``rules``), how it is built (``build``: default py_trees' decorator
    class of that name, called with its attributes) and how it ticks unlike the BT.CPP
    node it is exported as (``differences``).
    """

    def make(key: str, class_name: str, description: str, *extra: Attr,
             rules: tuple[Rule, ...] = (), build: str = "", differences: str = "") -> NodeKind:
        return NodeKind(key, category, class_name, description,
                        (name_attr(class_name), *extra, children, *CONDITION_ATTRS), rules,
                        build=build or _PY_TREES + class_name, differences=differences)

    return make


_composite = _maker(Category.COMPOSITE, _CHILDREN)
_decorator = _maker(Category.DECORATOR, _CHILD)


_PARALLEL_POLICIES = ("success_on_all", "success_on_one", "success_on_selected")
_STATUSES = ("success", "failure", "running")

_KIND_LIST: tuple[NodeKind, ...] = (
    _composite(
        "sequence", "Sequence", "Tick children in order until one does not succeed.", _MEMORY,
        build=_CONVERT + "sequence",
    ),
    _composite(
        "selector", "Selector", "Tick children in order until one does not fail.", _MEMORY,
        build=_CONVERT + "selector",
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
        build=_CONVERT + "parallel",
        differences="No BT.CPP node ticks alike, so it is exported as the custom SarParallel: "
        "py_trees ticks every child (with synchronise, all but those already succeeded), then "
        "fails if any failed; BT.CPP's Parallel stops at a threshold and ParallelAll waits for "
        "every child.",
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
        build=_CONVERT + "one_shot",
        differences="on_completion is exported as RunOnce then_skip=\"false\", which ticks "
        "alike; on_successful_completion has no BT.CPP node (RunOnce latches a failure too) "
        "and is exported as the custom SarOneShot.",
    ),
    _decorator("inverter", "Inverter", "Swap SUCCESS and FAILURE."),
    _decorator(
        "retry",
        "Retry",
        "Tick a failing child again until it has failed num_failures times in all.",
        Attr(
            "num_failures",
            AttrType.INTEGER,
            required=True,
            minimum=1,
            description="Attempts in all, the first included: the decorator fails on the "
            "num_failures-th failure.",
        ),
        build=_CONVERT + "retry",
        differences="Exported as RetryUntilSuccessful num_attempts=num_failures: both make that "
        "many attempts in all and count afresh after a success or a halt. A child that fails "
        "on its first tick is tried again on the next tick by both; one that was RUNNING "
        "before it failed is tried again on the next tick here, within the same tick by "
        "BT.CPP. BT.CPP's num_attempts also takes -1 (for ever) and 0 (FAILURE without "
        "ticking the child); num_failures is at least 1.",
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
        build=_CONVERT + "repeat",
        differences="Exported as Repeat num_cycles=num_success (-1: for ever in both). A "
        "child that succeeds on its first tick is ticked again on the next tick by both; one "
        "that was RUNNING before it succeeded is ticked again on the next tick here, within "
        "the same tick by BT.CPP.",
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
        build=_CONVERT + "timeout",
        differences="Exported as Timeout msec=duration*1000, rounded to milliseconds. Here "
        "the duration counts on the tree's clock (ROS time under the runner), in BT.CPP on "
        "the wall clock.",
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
        build=_CONVERT + "condition",
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

#: The script nodes' builder (their scripts, compiled by validation, and the blackboard).
_SCRIPTED = "sar_framework.engine.building.build:build_scripted"
#: The script nodes (BT.CPP 4's names; :mod:`.script_nodes`).
SCRIPT_KINDS: tuple[NodeKind, ...] = (
    NodeKind("Script", Category.LEAF, "Script", "Run a script; SUCCESS.", (
        name_attr("Script"),
        Attr("code", AttrType.SCRIPT, required=True, min_length=1,
             description="The script (e.g. 'count := count + 1')."),
        *CONDITION_ATTRS), build=_SCRIPTED),
    NodeKind("ScriptCondition", Category.LEAF, "ScriptCondition",
             "SUCCESS when the script's value is true, else FAILURE.", (
        name_attr("ScriptCondition"),
        Attr("code", AttrType.SCRIPT, required=True, min_length=1,
             description="The script; its last value is the condition."),
        *CONDITION_ATTRS), build=_SCRIPTED),
    _decorator(
        "Precondition", "Precondition",
        "Tick the child only when 'if' holds (checked again once the child is not running).",
        Attr("if", AttrType.SCRIPT, required=True, min_length=1,
             description="The condition script."),
        Attr("else", AttrType.STRING, default="FAILURE",
             enum=("SUCCESS", "FAILURE", "RUNNING", "SKIPPED"),
             description="The status when 'if' is false (the child is not ticked)."),
        build=_SCRIPTED,
    ),
)  # fmt: skip

#: Composite, decorator and script kinds by key, then BT.CPP's
#: (:mod:`.control_kinds`).
KINDS: dict[str, NodeKind] = {k.key: k for k in (*_KIND_LIST, *SCRIPT_KINDS, *CONTROL_KINDS)}
#: The kinds that build py_trees' own composites and decorators (the snake_case keys).
PY_TREES_KINDS: dict[str, NodeKind] = {k.key: k for k in _KIND_LIST}

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
        name_attr(plugin.name),
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
                AttrType.STRING if p.ref is not None else PARAM_ATTR_TYPES[p.type],
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
    return (*attrs, *CONDITION_ATTRS)


#: Top-level keys of a tree file, in the order the docs list them.
#: The values of a tree file's top-level ``completion`` key (see mission/completion.py).
TREE_COMPLETIONS = ("end", "once", "rest", "forever")

TOP_LEVEL_ATTRS: tuple[Attr, ...] = (
    Attr("format", AttrType.INTEGER, required=True, enum=(FORMAT_VERSION,),
         description="The tree format version; always 1."),
    Attr("name", AttrType.STRING, description="The tree's name (default: the file name)."),
    Attr("description", AttrType.STRING, description="Free text."),
    Attr("completion", AttrType.STRING, enum=TREE_COMPLETIONS,
         description="How a run of this tree ends: end (at its declared end, the default), "
         "once (the root's first SUCCESS or FAILURE), rest (when the tree is at rest) or "
         "forever (until Ctrl-C); the runner's completion parameter overrides it."),
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
