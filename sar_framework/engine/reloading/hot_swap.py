"""Hot swap: a running tree takes the nodes of a new tree file between two ticks.

::

    prepared = prepare_swap(loaded, "trees/search_and_rescue.yaml", context=context)
    # raises TreeLoadError (file:line:col diagnostics) and changes nothing when the new
    # file is invalid or cannot be built
    for behaviour in prepared.fresh:    # what was built: set it up (it may still fail)
        behaviour.setup(node=node)
    swap = prepared.commit()            # between two ticks
    tree.root = swap.tree.root          # the same root object when the root was kept
    print(swap.summary.line())          # "1 added (Wait); 1 changed (Dwell); 40 kept"

The plan is :mod:`.tree_diff`'s. Nodes whose spec is unchanged keep their behaviour
objects, so a leaf RUNNING a navigation goal goes on with it; a composite or decorator
whose own spec is unchanged keeps its object and its state (a memory sequence's current
child, a retry's count) and receives its new children. A node that leaves the tree while
RUNNING is halted the way its parent would halt it: ``stop(INVALID)``, whose
``terminate`` cancels goals in flight. Shared state is not the tree's: the context
objects (an app's own) are handed to the new behaviours unchanged, and the blackboard
keeps every entry's value (a new entry gets its initial value; an old one keeps its own).
The initial values given from outside the file (``sar-tree run --set``) hold for the new
file too: it is checked with them, as the first was.

Nothing is touched before the new tree is validated *and* built: a refused reload leaves
the running tree exactly as it was.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import py_trees
from py_trees.common import Status

from sar_framework.engine.api import LoadedTree, load_error, validate
from sar_framework.engine.building.build import build
from sar_framework.engine.building.port_values import write_initial
from sar_framework.engine.ports import NO_DEFAULT
from sar_framework.engine.registry import Registry
from sar_framework.engine.reloading.tree_diff import (
    Decision,
    SwapSummary,
    TreeDiff,
    diff_trees,
    summarise,
)
from sar_framework.engine.spec import NodeSpec

Behaviour = py_trees.behaviour.Behaviour
_REWIRABLE = (py_trees.composites.Sequence, py_trees.composites.Selector,
              py_trees.composites.Parallel, py_trees.decorators.Decorator)

__all__ = ["HotSwap", "PreparedSwap", "hot_swap", "prepare_swap"]


@dataclass
class HotSwap:
    """A swap done: the tree to tick from now on, and what changed.

    Attributes:
        tree: The new tree (its ``behaviours`` hold the kept objects where kept).
        summary: What was added, removed, changed, restarted, kept and halted.
        fresh: The behaviours built by the swap, which need their ``setup``.
    """

    tree: LoadedTree
    summary: SwapSummary
    fresh: list[Behaviour]


class PreparedSwap:
    """A new tree validated and built, not yet swapped in: set up :attr:`fresh`, then commit.

    Until :meth:`commit`, the running tree is untouched; dropping a prepared swap leaves it
    as it was.

    Attributes:
        fresh: The behaviours built for the new tree (each needs its ``setup``).
    """

    def __init__(self, old: LoadedTree, diff: TreeDiff, adopter: _Adopter,
                 new: LoadedTree) -> None:
        self._old, self._diff, self._adopter, self._new = old, diff, adopter, new
        self._built = dict(new.behaviours)
        self._known = {id(b) for b in old.root.iterate()}
        self._committed = False
        roots = [new.root, *(c for _, children, _ in adopter.rewires for c in children)]
        seen: set[int] = set()
        self.fresh: list[Behaviour] = []
        for top in roots:
            for behaviour in top.iterate():
                if id(behaviour) not in self._known and id(behaviour) not in seen:
                    seen.add(id(behaviour))
                    self.fresh.append(behaviour)

    def commit(self) -> HotSwap:
        """Swap: halt what leaves the tree while RUNNING, re-wire what stays (between ticks).

        Returns:
            The swap done.

        Raises:
            RuntimeError: It was committed already.
        """
        if self._committed:
            raise RuntimeError("this swap was committed already")
        self._committed = True
        old_keys, entries = self._old.spec.entries, self._new.spec.entries
        write_initial({key: entry.initial for key, entry in entries.items()
                       if entry.initial is not NO_DEFAULT and key not in old_keys})
        halted = _halt_discarded(self._diff, self._adopter.tops)
        for core, children, counterpart in self._adopter.rewires:
            _rewire(core, children, counterpart)
        behaviours = dict(self._built)
        for uid, decision in self._diff.decisions.items():
            if decision is not Decision.BUILD:
                behaviours[uid] = self._old.behaviours[self._diff.match[uid].uid]
        self._new.behaviours = behaviours
        return HotSwap(self._new, summarise(self._diff, tuple(halted)), self.fresh)


def prepare_swap(
    old: LoadedTree,
    path: str | Path,
    context: Mapping[str, Any] | None = None,
    *,
    registry: Registry | None = None,
    plugin_paths: Sequence[str | Path] = (),
) -> PreparedSwap:
    """Validate and build the tree in ``path`` for a swap with ``old``; change nothing yet.

    Args:
        old: The running tree, from ``load_tree`` or an earlier swap.
        path: The new tree file.
        context: The shared objects the new leaves receive (the running tree's).
        registry: The plugins to check against; default: built-ins and entry points.
        plugin_paths: Extra plugin files, dirs or modules.

    Returns:
        The swap, ready to :meth:`~PreparedSwap.commit`.

    Raises:
        TreeLoadError: The new file is invalid or cannot be built (every diagnostic), or
            does not take ``old``'s initial values (``--set``: an entry it no longer
            declares, a type the value does not convert to); ``old`` is untouched and goes
            on ticking.
    """
    result = validate(path, registry=registry, plugin_paths=plugin_paths,
                      initial_values=old.initial_values)
    if result.spec is None:
        raise load_error(path, result)
    rewirable = frozenset(uid for uid, behaviour in old.behaviours.items()
                          if isinstance(_core(behaviour), _REWIRABLE))
    diff = diff_trees(old.spec, result.spec, rewirable)
    adopter = _Adopter(old, diff, _tops(old))
    # No initial value is written yet: the new entries' are, on commit.
    root, built = build(result.spec, result.registry, context, adopter=adopter,
                        keep_entries=frozenset(result.spec.entries))
    return PreparedSwap(old, diff, adopter, LoadedTree(root, result.spec, built, result.registry,
                                                       old.initial_values))


def hot_swap(
    old: LoadedTree,
    path: str | Path,
    context: Mapping[str, Any] | None = None,
    *,
    registry: Registry | None = None,
    plugin_paths: Sequence[str | Path] = (),
) -> HotSwap:
    """Swap ``old`` (ticking) for the tree in ``path`` at once; call it between two ticks.

    :func:`prepare_swap` then :meth:`~PreparedSwap.commit` (set the fresh behaviours up
    after it).

    Args:
        old: The running tree.
        path: The new tree file.
        context: The shared objects the new leaves receive (the running tree's).
        registry: The plugins to check against; default: built-ins and entry points.
        plugin_paths: Extra plugin files, dirs or modules.

    Returns:
        The swap done.

    Raises:
        TreeLoadError: As :func:`prepare_swap`; ``old`` is untouched.
    """
    return prepare_swap(old, path, context, registry=registry,
                        plugin_paths=plugin_paths).commit()


def _core(behaviour: Behaviour) -> Behaviour:
    """A node's own behaviour: inside its pre/post-condition wrapper, if any."""
    from sar_framework.engine.nodes.script_nodes import PrePostConditions

    return behaviour.decorated if isinstance(behaviour, PrePostConditions) else behaviour


def _tops(tree: LoadedTree) -> dict[str, Behaviour]:
    """Each node's outermost behaviour (wrappers included): what its parent holds."""
    tops: dict[str, Behaviour] = {}
    stack: list[tuple[NodeSpec, Behaviour | None]] = [(tree.spec.root, None)]
    while stack:
        node, parent = stack.pop()
        top = tree.behaviours[node.uid]
        while top.parent is not None and top.parent is not parent:
            top = top.parent
        tops[node.uid] = top
        core = _core(tree.behaviours[node.uid])
        stack.extend((child, core) for child in node.children)
    return tops


class _Adopter:
    """Gives the builder the old behaviours the plan keeps; notes the re-wirings to do."""

    def __init__(self, old: LoadedTree, diff: TreeDiff, tops: dict[str, Behaviour]) -> None:
        self.old = old
        self.diff = diff
        self.tops = tops
        self.rewires: list[tuple[Behaviour, list[Behaviour], dict[int, Behaviour]]] = []

    def top(self, node: NodeSpec, make: Callable[[NodeSpec], Behaviour | None]
            ) -> Behaviour | None:
        decision = self.diff.decisions[node.uid]
        if decision is Decision.BUILD:
            return None
        old = self.diff.match[node.uid]
        if decision is Decision.REWIRE:
            children = [make(child) for child in node.children]
            if any(child is None for child in children):
                return None  # the builder has the problems; nothing is re-wired
            counterpart = {}
            for child, made in zip(node.children, children, strict=True):
                matched = self.diff.match.get(child.uid)
                if matched is not None:
                    counterpart[id(self.tops[matched.uid])] = made
            self.rewires.append((_core(self.old.behaviours[old.uid]),
                                 children, counterpart))  # type: ignore[arg-type]
        return self.tops[old.uid]

    def leaf(self, node: NodeSpec) -> Behaviour | None:
        if self.diff.decisions.get(node.uid) is not Decision.KEEP:
            return None
        return _core(self.old.behaviours[self.diff.match[node.uid].uid])


def _halt_discarded(diff: TreeDiff, tops: dict[str, Behaviour]) -> list[str]:
    """Halt every old behaviour that leaves the tree while RUNNING; name its running leaves."""
    halted: list[str] = []
    for node in diff.discarded():
        top = tops[node.uid]
        if top.status == Status.RUNNING:
            halted.extend(b.name for b in top.iterate()
                          if b.status == Status.RUNNING and not b.children)
            top.stop(Status.INVALID)
    return halted


def _rewire(core: Behaviour, children: list[Behaviour], counterpart: dict[int, Behaviour]
            ) -> None:
    """Give a kept composite or decorator its new children, keeping its place in them."""
    for child in children:
        child.parent = core
    if isinstance(core, py_trees.decorators.Decorator):
        core.decorated = children[0]
        core.children = [children[0]]
        return
    before = list(core.children)
    current = core.current_child
    core.children = list(children)
    policy_children = getattr(getattr(core, "policy", None), "children", None)
    if policy_children:  # a parallel's SuccessOnSelected names its children
        wanted = [c.name for c in policy_children]
        core.policy.children = [c for name in wanted for c in children if c.name == name]
    if current is None or any(current is c for c in children):
        return
    core.current_child = counterpart.get(id(current)) or _next_after(before, current, children)
    if (core.current_child is None and core.status == Status.RUNNING
            and getattr(core, "memory", False)):
        # A memory sequence/selector resumes at its current child: with nothing left after
        # the children it had passed, it starts over when next ticked.
        core.stop(Status.INVALID)


def _next_after(before: list[Behaviour], current: Behaviour, children: list[Behaviour]
                ) -> Behaviour | None:
    """The new child after the last child kept from before the removed ``current``."""
    position = 0
    for old in before[:before.index(current)]:
        for index, child in enumerate(children):
            if child is old:
                position = index + 1
    return children[position] if position < len(children) else None
