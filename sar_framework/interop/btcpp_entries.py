"""Blackboard entries of an imported BT.CPP file: who reads and who writes ``{key}``.

Every ``{key}`` port binding the importer meets is a :class:`Use` (read, write or both,
with the port's type when known). A ``<SubTree>`` insertion carries its inner tree's uses
out to the parent as BT.CPP's blackboards do: a port remapped ``inner="{outer}"`` becomes a
use of ``outer``, with ``_autoremap="true"`` every other entry too, and ``{@key}`` (the
root blackboard) always. The main tree's entries that something reads and nothing writes
are the inputs the caller must set (Nav2's ``{goal}``); a scope that declares one must
declare them all, so :func:`blackboard_declarations` declares every entry, for the tree
file's ``blackboard:`` section.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from sar_framework.interop.btcpp_models import NodeModel, convert_literal


@dataclass(frozen=True)
class Use:
    """One port bound to a blackboard entry.

    Attributes:
        entry: The entry name as written inside the braces (``goal``, ``@goal``).
        reads: Whether the port reads it (input or inout).
        writes: Whether the port writes it (output or inout).
        type: Our port type name (``any`` when unknown).
        node: Who uses it (``<ComputePathToPose> port 'goal'``), for the description.
        element: Where the using node is (``file:line:col``): one node, several ports.
    """

    entry: str
    reads: bool
    writes: bool
    type: str = "any"
    node: str = ""
    element: str = ""


@dataclass(frozen=True)
class Insertion:
    """One ``<SubTree>`` inside a tree.

    Attributes:
        tree: The inserted tree's ID.
        ports: Inner port -> the value given (``{outer}`` or a literal).
        autoremap: ``_autoremap="true"``.
    """

    tree: str
    ports: dict[str, str]
    autoremap: bool


@dataclass
class TreeUses:
    """The uses and insertions of one ``<BehaviorTree>``."""

    uses: list[Use] = field(default_factory=list)
    insertions: list[Insertion] = field(default_factory=list)


def entry_key(value: str) -> str | None:
    """The entry of a ``{key}`` value (``{=}`` is not resolved here), else None."""
    text = value.strip()
    if len(text) >= 3 and text[0] == "{" and text[-1] == "}":
        return text[1:-1].strip()
    return None


def effective_uses(tree: str, trees: dict[str, TreeUses],
                   seen: frozenset[str] = frozenset()) -> list[Use]:
    """The uses of ``tree``'s own blackboard, its subtrees' carried out to it."""
    if tree in seen or tree not in trees:
        return []
    found = list(trees[tree].uses)
    for insertion in trees[tree].insertions:
        inner_uses = effective_uses(insertion.tree, trees, seen | {tree})
        for use in inner_uses:
            outer = _outer(use.entry, insertion)
            if outer is not None:
                found.append(Use(outer, use.reads, use.writes, use.type, use.node,
                                 use.element))
    return found


def _outer(entry: str, insertion: Insertion) -> str | None:
    if entry.startswith("@"):
        return entry
    if entry in insertion.ports:
        value = insertion.ports[entry]
        if value.strip() == "{=}":
            return entry
        return entry_key(value)
    return entry if insertion.autoremap else None


def blackboard_declarations(uses: list[Use], source: str, *,
                            skip: frozenset[str] = frozenset()) -> dict[str, dict[str, Any]]:
    """Every entry of a scope as a ``blackboard:`` declaration (no ``initial``).

    A scope that declares entries must declare every name it uses (the validator reports
    the others), so all are declared: the type is the first writer's, else the first
    reader's (``any`` when none says); the description says who writes and reads it, and
    ``Set by the caller`` when it is read before anything writes it (Nav2's ``{goal}``).

    Args:
        uses: The scope's uses (:func:`effective_uses`).
        source: The file name, for the descriptions.
        skip: Names declared elsewhere (a subtree's ports).

    Returns:
        Entry name (without ``@``) -> ``{type, description}``, in first-use order.
    """
    writers: dict[str, list[Use]] = {}
    readers: dict[str, list[Use]] = {}
    for use in uses:
        name = use.entry.lstrip("@")
        if name in skip:
            continue
        writers.setdefault(name, [])
        readers.setdefault(name, [])
        (writers if use.writes else readers)[name].append(use)
        if use.writes and use.reads:
            readers[name].append(use)
    declared: dict[str, dict[str, Any]] = {}
    inputs = set(caller_inputs(uses))
    for name, written_by in writers.items():
        typed = [u.type for u in written_by + readers[name] if u.type != "any"]
        who = _names(written_by)
        text = f"Written by {who}" if who else f"Nothing in {source} writes it"
        if name in inputs:
            text = f"Set by the caller ({text[0].lower()}{text[1:]}, after it is read)" \
                if who else f"Set by the caller: nothing in {source} writes it"
        if readers[name]:
            text += f"; read by {_names(readers[name])}"
        declared[name] = {"type": typed[0] if typed else "any", "description": text + "."}
    return declared


def _names(uses: list[Use]) -> str:
    nodes = list(dict.fromkeys(use.node for use in uses if use.node))
    return ", ".join(nodes[:3]) + (f" and {len(nodes) - 3} more" if len(nodes) > 3 else "")


def caller_inputs(uses: list[Use]) -> list[str]:
    """The entries (without ``@``) the caller must set, in first-use order.

    Those read that nothing writes (Nav2's ``{goal}``), and those whose only writers read
    them first (Nav2's ``{goals}``: ``RemovePassedGoals`` reads it, then writes it back).
    An entry some other node writes is not one, even when a reader comes first in the file
    (Nav2's ``IsPathValid`` of ``{path}`` before ``ComputePathToPose``: BT.CPP's reader
    fails until the path exists).
    """
    read_at: dict[str, set[str]] = {}
    written_at: dict[str, set[str]] = {}
    for use in uses:
        name = use.entry.lstrip("@")
        read_at.setdefault(name, set())
        written_at.setdefault(name, set())
        if use.reads:
            read_at[name].add(use.element)
        if use.writes:
            written_at[name].add(use.element)
    return [name for name, readers in read_at.items()
            if readers and written_at[name] <= readers]


def subtree_ports(tree: str, trees: dict[str, TreeUses], passed: list[str],
                  defaults: dict[str, str]) -> dict[str, dict[str, Any]]:
    """The ``ports:`` declaration of a subtree definition.

    Args:
        tree: The subtree's ID.
        trees: Every tree's uses.
        passed: The ports its insertions remap (``<SubTree ID=tree port=...>``).
        defaults: Port -> default, from its ``<SubTree>`` model.

    Returns:
        Port -> ``{direction, type[, default]}``: the direction from how the subtree uses
        the entry (read: input, written: output, both: inout), the type from its users.
    """
    uses = effective_uses(tree, trees)
    declared: dict[str, dict[str, Any]] = {}
    for name in [*passed, *(d for d in defaults if d not in passed)]:
        mine = [use for use in uses if use.entry == name]
        reads = any(use.reads for use in mine) or not mine
        writes = any(use.writes for use in mine)
        kind = next((use.type for use in mine if use.type != "any"), "any")
        direction = "inout" if reads and writes else ("output" if writes else "input")
        entry: dict[str, Any] = {"direction": direction, "type": kind}
        if name in defaults and direction != "output":
            entry["default"] = defaults[name]
        declared[name] = entry
    return declared


def subtree_definition(tree: str, body: Any, trees: dict[str, TreeUses], *,
                       insertions: list[Insertion], uses_written: list[dict[str, Any]],
                       model: NodeModel | None, source: str) -> Any:
    """A subtree's definition: its root, or the long form when it has ports.

    Args:
        tree: The subtree's ID.
        body: Its root node, imported.
        trees: Every tree's uses.
        insertions: Every ``<SubTree ID=tree>`` of the file.
        uses_written: The ``subtree: {tree, ports}`` bodies written for those insertions;
            their literal port values are converted to the declared port types.
        model: Its ``<SubTree>`` model, if any.
        source: The file it is defined in, for descriptions.

    Returns:
        ``body``, or ``{ports, blackboard (private entries, when no insertion
        autoremaps), root}``.
    """
    passed = list(dict.fromkeys(name for i in insertions for name in i.ports))
    defaults = {p.name: p.default for p in model.ports if p.default is not None} \
        if model is not None and model.category == "SubTree" else {}
    if not passed and not defaults:
        return body
    ports = subtree_ports(tree, trees, passed, defaults)
    for entry in ports.values():
        if "default" in entry and entry_key(entry["default"]) is None:
            entry["default"] = convert_literal(entry["default"], entry["type"])
    for use in uses_written:
        for name, value in use.get("ports", {}).items():
            if name in ports and entry_key(value) is None:
                use["ports"][name] = convert_literal(value, ports[name]["type"])
    definition: dict[str, Any] = {"ports": ports}
    if not any(i.autoremap for i in insertions):
        private = blackboard_declarations(effective_uses(tree, trees), source,
                                          skip=frozenset(ports))
        if private:
            definition["blackboard"] = private
    definition["root"] = body
    return definition
