"""What changed between two validated trees, node by node: the plan of a hot swap.

A node is identified by its *path*: the kind, name and occurrence (among siblings of the
same kind and name) of itself and of every ancestor. Unlike a uid (child indices), a path
survives a sibling added or removed before it. Two nodes with the same path are compared
by their *own spec* (kind, attrs, id, ports, bindings, scripts, the paths of the leaves
they reference, the subtree insertion) and by their *whole spec* (their own spec and their
children's whole specs, in order).

Each node of the new tree gets one :class:`Decision`:

- ``KEEP``: its whole spec is unchanged and every ancestor is kept or re-wired: the old
  behaviour (and its subtree) goes on as it is, state and all;
- ``REWIRE``: its own spec is unchanged, only its children differ, and it is a py_trees
  ``Sequence``, ``Selector``, ``Parallel`` or a decorator: the old behaviour stays and
  receives the new list of children;
- ``BUILD``: a new behaviour (added, changed, or restarted under a rebuilt ancestor).

A kept leaf holding a reference to a leaf that is rebuilt is rebuilt too (it must hold the
behaviour that will be ticked).
"""

from __future__ import annotations

import enum
from collections.abc import Iterator
from dataclasses import dataclass, field

from sar_framework.engine.spec import NodeSpec, TreeSpec

Path = tuple[tuple[str, str, int], ...]


class Decision(enum.Enum):
    """What a hot swap does with one node of the new tree."""

    KEEP = "keep"
    REWIRE = "rewire"
    BUILD = "build"


def paths(root: NodeSpec) -> dict[str, Path]:
    """Every node's path, by uid."""
    found: dict[str, Path] = {root.uid: (("", root.kind, 0),)}
    for node in root.walk():
        seen: dict[tuple[str, str], int] = {}
        for child in node.children:
            key = (child.kind, child.name)
            count = seen.get(key, 0)
            seen[key] = count + 1
            found[child.uid] = (*found[node.uid], (child.kind, child.name, count))
    return found


def own_spec(node: NodeSpec, where: dict[str, Path]) -> str:
    """A node's own spec as text (children left out), for comparison."""
    refs = sorted((name, where.get(target.uid, ())) for name, target in node.refs.items())
    use = own_spec(node.use, where) if node.use is not None else ""
    return repr((node.kind, node.name, sorted(node.attrs.items(), key=lambda kv: kv[0]),
                 node.id, refs, node.subtree, sorted(node.ports.items()),
                 sorted(node.bindings.items()), sorted(node.scripts.items()),
                 sorted(node.script_keys.items()), sorted(node.insertion.items()), use))


def _whole_specs(root: NodeSpec, where: dict[str, Path]) -> dict[str, str]:
    whole: dict[str, str] = {}
    for node in reversed(list(root.walk())):  # children before parents
        whole[node.uid] = repr((own_spec(node, where), [whole[c.uid] for c in node.children]))
    return whole


@dataclass
class TreeDiff:
    """The plan of a hot swap from ``old`` to ``new``.

    Attributes:
        old: The running tree's spec.
        new: The new tree's spec.
        match: New uid -> the old node at the same path.
        decisions: New uid -> what the swap does with it.
        rewirable: Old uids whose behaviour can take a new list of children.
        old_paths: Old uid -> path.
        new_paths: New uid -> path.
    """

    old: TreeSpec
    new: TreeSpec
    match: dict[str, NodeSpec] = field(default_factory=dict)
    decisions: dict[str, Decision] = field(default_factory=dict)
    rewirable: frozenset[str] = frozenset()
    old_paths: dict[str, Path] = field(default_factory=dict)
    new_paths: dict[str, Path] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.old_whole = _whole_specs(self.old.root, self.old_paths)
        self.new_whole = _whole_specs(self.new.root, self.new_paths)

    def same_own(self, old: NodeSpec, new: NodeSpec) -> bool:
        """Whether ``old`` and ``new`` have the same own spec."""
        return own_spec(old, self.old_paths) == own_spec(new, self.new_paths)

    def same_whole(self, old: NodeSpec, new: NodeSpec) -> bool:
        """Whether ``old`` and ``new`` have the same whole spec (children included)."""
        return self.old_whole[old.uid] == self.new_whole[new.uid]

    def reused(self) -> set[str]:
        """The old uids whose behaviours go on in the new tree."""
        return {self.match[uid].uid for uid, d in self.decisions.items()
                if d is not Decision.BUILD}

    def removed(self) -> list[NodeSpec]:
        """Old nodes no new node has the path of."""
        matched = {node.uid for node in self.match.values()}
        return [node for node in self.old.nodes() if node.uid not in matched]

    def discarded(self) -> Iterator[NodeSpec]:
        """The topmost old nodes whose behaviours leave the tree (each with its subtree)."""
        decided = {self.match[uid].uid: d for uid, d in self.decisions.items()
                   if uid in self.match}
        stack = [self.old.root]
        while stack:
            node = stack.pop()
            decision = decided.get(node.uid, Decision.BUILD)
            if decision is Decision.BUILD:
                yield node
            elif decision is Decision.REWIRE:
                stack.extend(node.children)


def diff_trees(old: TreeSpec, new: TreeSpec, rewirable: frozenset[str]) -> TreeDiff:
    """Decide, node by node, what a hot swap from ``old`` to ``new`` keeps.

    Args:
        old: The running tree's spec.
        new: The new tree's spec.
        rewirable: Old uids whose behaviours can take a new list of children.

    Returns:
        The plan.
    """
    old_paths, new_paths = paths(old.root), paths(new.root)
    by_path = {path: node for node in old.nodes() for path in (old_paths[node.uid],)}
    match = {node.uid: by_path[new_paths[node.uid]] for node in new.nodes()
             if new_paths[node.uid] in by_path}
    diff = TreeDiff(old, new, match, rewirable=rewirable, old_paths=old_paths,
                    new_paths=new_paths)
    forced: set[str] = set()
    while True:
        diff.decisions = _decide(diff, forced)
        stale = {node.uid for node in new.nodes()
                 if diff.decisions[node.uid] is Decision.KEEP
                 and any(diff.decisions[t.uid] is not Decision.KEEP for t in node.refs.values())}
        if stale <= forced:
            return diff
        forced |= stale


def _decide(diff: TreeDiff, forced: set[str]) -> dict[str, Decision]:
    decisions: dict[str, Decision] = {}
    stack: list[tuple[NodeSpec, bool]] = [(diff.new.root, True)]
    while stack:
        node, parent_reused = stack.pop()
        old = diff.match.get(node.uid)
        if old is None or not parent_reused:
            decisions[node.uid] = Decision.BUILD
        elif diff.same_whole(old, node) and not any(d.uid in forced for d in node.walk()):
            for inner in node.walk():
                decisions[inner.uid] = Decision.KEEP
            continue
        elif old.uid in diff.rewirable and node.uid not in forced and diff.same_own(old, node):
            decisions[node.uid] = Decision.REWIRE
        else:
            decisions[node.uid] = Decision.BUILD
        reused = decisions[node.uid] is Decision.REWIRE
        stack.extend((child, reused) for child in reversed(node.children))
    return decisions


@dataclass(frozen=True)
class SwapSummary:
    """What a hot swap changed, by node name.

    Attributes:
        added: New nodes no old node has the path of.
        removed: Old nodes no new node has the path of.
        changed: Nodes whose spec changed (rebuilt).
        restarted: Nodes whose spec is unchanged, rebuilt with a rebuilt ancestor or
            reference.
        kept: Nodes whose behaviour goes on (state and all).
        halted: Running leaves the swap halted (their goals cancelled).
    """

    added: tuple[str, ...] = ()
    removed: tuple[str, ...] = ()
    changed: tuple[str, ...] = ()
    restarted: tuple[str, ...] = ()
    kept: tuple[str, ...] = ()
    halted: tuple[str, ...] = ()

    def line(self) -> str:
        """One line for the console and the event: counts, and the names that moved."""
        parts = []
        for label in ("added", "removed", "changed", "restarted"):
            names = getattr(self, label)
            if names:
                parts.append(f"{len(names)} {label} ({', '.join(names)})")
        parts.append(f"{len(self.kept)} kept")
        if self.halted:
            parts.append(f"halted {', '.join(self.halted)}")
        return "; ".join(parts)


def summarise(diff: TreeDiff, halted: tuple[str, ...] = ()) -> SwapSummary:
    """Name what ``diff`` adds, removes, changes, restarts and keeps."""
    added: list[str] = []
    changed: list[str] = []
    restarted: list[str] = []
    kept: list[str] = []
    for node in diff.new.nodes():
        old = diff.match.get(node.uid)
        decision = diff.decisions[node.uid]
        if old is None:
            added.append(node.name)
        elif decision is not Decision.BUILD:
            kept.append(node.name)
        elif not diff.same_own(old, node) or (old.uid not in diff.rewirable
                                              and not diff.same_whole(old, node)):
            changed.append(node.name)
        else:
            restarted.append(node.name)
    removed = tuple(node.name for node in diff.removed())
    return SwapSummary(tuple(added), removed, tuple(changed), tuple(restarted), tuple(kept),
                       halted)
