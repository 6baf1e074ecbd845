"""BehaviorTree.CPP 4's nodes as node kinds, keyed by their BT.CPP IDs.

A tree file writes them as BT.CPP names them (``SequenceWithMemory``, ``Parallel``,
``Timeout``), with BT.CPP's port names as attributes; each declaration names (``build``)
the behaviour of :mod:`sar_framework.engine.nodes.controls` or ``.decorators`` that ticks
like the original, or the builder that makes it. The snake_case kinds
of :mod:`.node_kinds` (``sequence``, ``parallel``, ``retry``...) stay py_trees' own
behaviours: where both exist (``sequence`` / ``Sequence``), the snake_case key means
py_trees' semantics and the BT.CPP key BT.CPP's.

Most of BT.CPP's ports are literals here (params). The integers BT.CPP reads with
``getInput`` (Timeout's ``msec``, Repeat's ``num_cycles``... a kind's ``reads``) are
ports: a literal (range-checked) or ``{name}``, read when BT.CPP reads it. The attributes
that read or write the blackboard are ports (:class:`~.ports.Port`, with a direction and a
type), resolved in the node's scope as a leaf's ports are (subtree scopes, ``{@name}``,
remapping) and checked with them: Switch's ``variable`` and cases, SetBlackboard's
``value`` (a literal or ``{name}``, read), the Loops' ``queue`` (a literal or ``{name}``
of a shared list) and ``value`` (``{name}``, written), and the ports BT.CPP reads as an
entry's *name* (:class:`~.ports.Naming`): SetBlackboard's ``output_key`` and
UnsetBlackboard's ``key`` (``name``), the ``entry`` of SkipUnlessUpdated, WaitValueUpdate
and WasEntryUpdated (``name`` or ``{name}``).

:func:`control_kind`, :func:`decorator_kind`, :func:`int_port` and :func:`port_attr` are
how a plugin declares its own controls and decorators too (:mod:`~..kind_plugin`).
"""

from __future__ import annotations

from typing import Any

from sar_framework.engine.nodes.kind_model import (
    CONDITION_ATTRS,
    Attr,
    AttrType,
    BuildRef,
    NodeKind,
    name_attr,
)
from sar_framework.engine.ports import NO_DEFAULT, Direction, Naming, Port
from sar_framework.engine.spec import Category

#: LoopInt..LoopString: the type of their items, in words and as a port type.
LOOP_ITEMS = {"LoopInt": "integer", "LoopBool": "boolean", "LoopDouble": "number",
              "LoopString": "string"}
LOOP_TYPES = {"LoopInt": "int", "LoopBool": "bool", "LoopDouble": "float", "LoopString": "str"}
#: Switch2..Switch6: the number of cases of each.
SWITCH_CASES = {f"Switch{n}": n for n in range(2, 7)}


def children_attr(minimum: int = 1, maximum: int | None = None, text: str = "") -> Attr:
    """The ``children`` of a control: at least ``minimum``, at most ``maximum``."""
    return Attr("children", AttrType.NODES, required=True, min_items=minimum,
                max_items=maximum, description=text or "The child nodes, in order.")


_CHILD = Attr("child", AttrType.NODE, required=True, description="The decorated node.")


def int_port(name: str, text: str, *, default: int | None = None,
             minimum: int | None = None) -> Attr:
    """An integer BT.CPP reads with ``getInput``: a literal (range-checked) or ``{name}``."""
    port = Port(name, "int", NO_DEFAULT if default is None else default, text)
    return Attr(name, AttrType.PORT, required=default is None, default=default,
                minimum=minimum, description=text, port=port)


def _bool_port(name: str, text: str, *, default: bool) -> Attr:
    """A boolean BT.CPP reads with ``getInput``: a literal or ``{name}``."""
    return Attr(name, AttrType.PORT, default=default, description=text,
                port=Port(name, "bool", default, text))


def port_attr(name: str, type_: str, text: str, *, direction: Direction = Direction.INPUT,
              naming: Naming = Naming.VALUE, required: bool = True, optional: bool = False
              ) -> Attr:
    """An attribute that is a blackboard port of the node (see the module docstring).

    ``optional``: an input the tree may leave unbound (its builder then reads a default
    entry, as BT.CPP's ``getInputOrBlackboard``).
    """
    port = Port(name, type_, NO_DEFAULT, text, direction, naming=naming, optional=optional)
    return Attr(name, AttrType.PORT, required=required and not optional, description=text,
                port=port)


def _entry() -> Attr:
    return port_attr("entry", "any", "The watched entry, by name: 'name' or '{name}'.",
                 naming=Naming.NAME)


def control_kind(key: str, text: str, *attrs: Attr, children: Attr | None = None,
                 symbol: str = "[-]", **how: Any) -> NodeKind:
    """A control node's declaration: its key, one line of docs, its attributes, children.

    ``symbol``: its text symbol in diagrams; ``how``: how it is built and read
    (``build``, ``context``, ``reads``, ``reads_each_tick``, ``reads_keep_default``,
    ``spellings``, ``reports``; see
    :class:`~.kind_model.NodeKind`).
    """
    return NodeKind(key, Category.COMPOSITE, key, text,
                    (name_attr(key), *attrs, children or children_attr(), *CONDITION_ATTRS),
                    symbol=symbol, **how)


def decorator_kind(key: str, text: str, *attrs: Attr, **how: Any) -> NodeKind:
    """A decorator's declaration: its key, one line of docs, its attributes (one child).

    ``how``: as :func:`control_kind`'s.
    """
    return NodeKind(key, Category.DECORATOR, key, text,
                    (name_attr(key), *attrs, _CHILD, *CONDITION_ATTRS), **how)


def _leaf(key: str, text: str, *attrs: Attr, **how: Any) -> NodeKind:
    return NodeKind(key, Category.LEAF, key, text, (name_attr(key), *attrs, *CONDITION_ATTRS),
                    **how)


#: Where the behaviours and the builders of BT.CPP's kinds are (named, not imported).
_NODES = "sar_framework.engine.nodes"
_BUILD = "sar_framework.engine.building.control_build:"


def _in(module: str, key: str) -> BuildRef:
    """The behaviour class ``key`` of ``sar_framework.engine.nodes.<module>``."""
    return f"{_NODES}.{module}:{key}"


def _switch(key: str, cases: int) -> NodeKind:
    case_attrs = [port_attr(f"case_{i}", "any", f"The value that selects child {i}: a literal, "
                        "or '{name}' to read that entry.") for i in range(1, cases + 1)]
    return control_kind(
        key, f"Tick the child of the first of {cases} cases the variable matches, else the "
        "last child.",
        port_attr("variable", "any", "The value compared (as text) with the cases: '{name}' "
              "reads that entry; a literal is compared as it is."),
        *case_attrs,
        children=children_attr(cases + 1, cases + 1, f"One child per case, then the default "
                           f"({cases + 1} children)."),
        build=_BUILD + "switch",
    )


#: The threshold ports of the parallels, which must not exceed the number of children.
_THRESHOLDS = {"Parallel": ("success_count", "failure_count"), "ParallelAll": ("max_failures",)}


def threshold_problem(kind: str, attrs: dict[str, object], children: int) -> str | None:
    """Why a parallel's threshold can never be reached with ``children``, or None."""
    for port in _THRESHOLDS.get(kind, ()):
        value = attrs.get(port)
        if isinstance(value, int) and not isinstance(value, bool):
            needed = max(children + value + 1, 0) if value < 0 else value
            if needed > children:
                return (f"'{port}' {value} is more than the {children} children of this "
                        f"{kind}: it could never be reached")
    return None


_BRANCHES = children_attr(2, 3, "The condition, the then-branch and an optional else-branch.")
_THRESHOLD = ("; negative counts from the number of children (-1: all of them)")

def _plain_controls(module: str, *kinds: tuple[str, str, str]) -> tuple[NodeKind, ...]:
    """Controls of ``module`` built as their class is: ``(key, one line, symbol)`` each."""
    return tuple(control_kind(key, text, symbol=symbol, build=_in(module, key))
                 for key, text, symbol in kinds)


def _converter(key: str, text: str) -> NodeKind:
    return decorator_kind(key, text, build=_in("decorators.converters", key))


CONTROL_KINDS: tuple[NodeKind, ...] = (
    *_plain_controls(
        "controls.sequences",
        ("Sequence", "Children in order until one fails; resumes at a running child.", "{-}")),
    control_kind("SequenceWithMemory", "Like Sequence, but a failed child is ticked again next "
                 "time instead of the first.", symbol="{-}",
                 build=_in("controls.sequences", "SequenceWithMemory"),
                 spellings=("SequenceStar",)),  # BT.CPP 3's name
    *_plain_controls(
        "controls.sequences",
        ("ReactiveSequence", "Every tick from the first child; a failure stops, a running "
         "child halts the others.", "[-]"),
        ("AsyncSequence", "Like Sequence, but returns RUNNING after each child that "
         "succeeds on its first tick.", "{-}"),
        ("AsyncFallback", "Like Fallback, but returns RUNNING after each child that fails "
         "on its first tick.", "{o}"),
        ("Fallback", "Children in order until one succeeds; resumes at a running child.",
         "{o}"),
        ("ReactiveFallback", "Every tick from the first child; a success stops, a running "
         "child halts the others.", "[o]")),
    control_kind("Parallel", "Every unfinished child each tick; SUCCESS or FAILURE once a "
             "threshold is reached.",
             int_port("success_count", "Successes needed" + _THRESHOLD, default=-1),
             int_port("failure_count", "Failures that fail it" + _THRESHOLD, default=1),
             symbol="/_/", build=_in("controls.parallels", "Parallel"),
             reads=("success_count", "failure_count")),
    control_kind("ParallelAll", "Every unfinished child each tick until all finished; FAILURE "
             "when max_failures failed.",
             int_port("max_failures", "Failures that make it fail" + _THRESHOLD, default=1),
             symbol="/_/", build=_in("controls.parallels", "ParallelAll"),
             reads=("max_failures",)),
    control_kind("IfThenElse", "The condition once, then the branch it chose until that "
             "completes.", children=_BRANCHES, build=_in("controls.conditionals", "IfThenElse")),
    control_kind("WhileDoElse", "The condition every tick, then its branch; switching halts the "
             "other branch.", children=_BRANCHES,
             build=_in("controls.conditionals", "WhileDoElse")),
    *(_switch(key, cases) for key, cases in SWITCH_CASES.items()),
    _converter("Inverter", "SUCCESS becomes FAILURE and FAILURE SUCCESS."),
    _converter("ForceSuccess", "A completed child gives SUCCESS."),
    _converter("ForceFailure", "A completed child gives FAILURE."),
    _converter("KeepRunningUntilFailure", "RUNNING until the child fails."),
    decorator_kind("Repeat", "Tick a succeeding child num_cycles times; a failure fails.",
               int_port("num_cycles", "Successes needed; -1 repeats forever.", minimum=-1),
               build=_in("decorators.loops", "Repeat"), reads=("num_cycles",)),
    decorator_kind("RetryUntilSuccessful", "Tick a failing child up to num_attempts times.",
               int_port("num_attempts", "Attempts allowed, the first included (0: none, "
                        "FAILURE at once); -1 retries forever.", minimum=-1),
               build=_in("decorators.loops", "RetryUntilSuccessful"), reads=("num_attempts",)),
    decorator_kind("RunOnce", "Tick the child until it completes once; then skip, or repeat "
               "that result.",
               _bool_port("then_skip", "After the first completion: SKIPPED (true) or the "
                          "same result (false).", default=True),
               build=_in("decorators.loops", "RunOnce"), reads=("then_skip",),
               reads_keep_default=True),
    decorator_kind("Delay", "RUNNING for delay_msec, then tick the child.",
               int_port("delay_msec", "Milliseconds before the child's first tick.",
                         minimum=0),
               build=_in("decorators.timing", "Delay"), context=("clock",),
               reads=("delay_msec",), reads_each_tick=False),
    decorator_kind("Timeout", "Halt the child and fail if it still runs after msec.",
               int_port("msec", "Milliseconds the child may run (0: no limit).", minimum=0),
               build=_in("decorators.timing", "Timeout"), context=("clock",),
               reads=("msec",), reads_each_tick=False),
    decorator_kind("SkipUnlessUpdated", "SKIPPED unless the entry was written since the last "
               "tick of the child.", _entry(), build=_BUILD + "updated_decorator"),
    decorator_kind("WaitValueUpdate", "RUNNING until the entry was written since the last tick "
               "of the child.", _entry(), build=_BUILD + "updated_decorator"),
    *(decorator_kind(key, f"Pop the next {kind} of queue into value and tick the child; RUNNING "
                 "while values remain, if_empty once the queue is empty.",
                 port_attr("queue", "list", f"The {kind}s: 'a;b;c', or '{{name}}' of a shared "
                       "list (its values are popped from it)."),
                 Attr("if_empty", AttrType.STRING, default="SUCCESS",
                      enum=("SUCCESS", "FAILURE", "SKIPPED"),
                      description="What to return once the queue is empty."),
                 port_attr("value", LOOP_TYPES[key], "The entry each value is written to: "
                       "'{name}'.", direction=Direction.OUTPUT, required=False),
                 build=_BUILD + "loop")
      for key, kind in LOOP_ITEMS.items()),
    _leaf("WasEntryUpdated", "SUCCESS if the entry was written since the last tick, else "
          "FAILURE.", _entry(), build=_BUILD + "was_updated"),
    _leaf("AlwaysSuccess", "SUCCESS.", build=_in("controls.leaves", "AlwaysSuccess")),
    _leaf("AlwaysFailure", "FAILURE.", build=_in("controls.leaves", "AlwaysFailure")),
    _leaf("Sleep", "RUNNING for msec milliseconds, then SUCCESS.",
          int_port("msec", "Milliseconds to wait.", minimum=0),
          build=_in("controls.leaves", "Sleep"), context=("clock",), reads=("msec",),
          reads_each_tick=False),
    _leaf("SetBlackboard", "Write value (a literal, or '{entry}' to copy one) to output_key.",
          port_attr("value", "any", "The value written: a literal, or '{name}' to copy that "
                "entry's value."),
          port_attr("output_key", "any", "The entry written, by name: 'name' (BT.CPP reads "
                "'{name}' as the entry whose name that entry holds).",
                direction=Direction.OUTPUT, naming=Naming.BARE_NAME),
          build=_BUILD + "set_blackboard"),
    _leaf("UnsetBlackboard", "Remove the entry key.",
          port_attr("key", "any", "The entry removed, by name: 'name' (BT.CPP reads '{name}' as "
                "the entry whose name that entry holds).", direction=Direction.OUTPUT,
                naming=Naming.BARE_NAME),
          build=_BUILD + "unset_blackboard"),
)

#: Kinds that write one port's value to another port's entry: kind -> (source, destination).
#: BT.CPP's SetBlackboard parses a literal into a typed destination, and copies an entry.
COPIES = {"SetBlackboard": ("value", "output_key")}
#: The attributes that are blackboard ports, in any kind (``"{name}"`` is an entry there).
ENTRY_PORTS = frozenset(a.name for k in CONTROL_KINDS for a in k.attrs if a.port is not None)
