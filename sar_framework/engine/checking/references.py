"""References between leaves: each reference param pointed at its leaf, cycles reported.

A reference param (``detector: detect``) names the ``id`` of a leaf visible in its scope
(the tree, or the subtree copy and the scopes around it); the referenced leaf must be of
the plugin the param declares, and references must not form a cycle (the builder builds
a referenced leaf first).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from sar_framework.engine.checking.entries import Report
from sar_framework.engine.diagnostics import SourceLocation, did_you_mean
from sar_framework.engine.spec import NodeSpec


def resolve_references(
    pending: list[tuple[NodeSpec, Any]],
    declaration: Callable[[str], Any],
    value_locs: dict[tuple[SourceLocation, str], Any],
    error: Report,
) -> None:
    """Point every reference param at its leaf; report dangling, mistyped, cyclic ones.

    Args:
        pending: Each leaf with reference params, with its id scope (``find``, ``visible``).
        declaration: The declaration of a node kind (its ``ref_params``).
        value_locs: Where each param's value stands: ``(leaf location, param) -> location``.
        error: Where problems go.
    """
    edges: dict[int, list[NodeSpec]] = {}
    for leaf, scope in pending:
        decl = declaration(leaf.kind)
        for param in decl.ref_params if decl is not None else ():
            ident = leaf.attrs.get(param.name)
            if not isinstance(ident, str):
                continue
            where = value_locs.get((leaf.location, param.name), leaf.location)
            target = scope.find(ident)
            if target is None:
                error(where, f"'{param.name}' names no leaf: there is no id "
                             f"'{ident}'{did_you_mean(ident, scope.visible())}")
            elif target.kind != param.ref:
                error(where, f"'{param.name}' must name a {param.ref} leaf, "
                             f"but '{ident}' is a {target.kind}")
            else:
                leaf.refs[param.name] = target
                edges.setdefault(id(leaf), []).append(target)
    reference_cycles(pending, edges, error)


def reference_cycles(
    pending: list[tuple[NodeSpec, Any]], edges: dict[int, list[NodeSpec]], error: Report
) -> None:
    """Report each cycle of references between leaves, once."""
    state: dict[int, int] = {}  # 1: on the path, 2: done
    for leaf, _ in pending:
        if id(leaf) in state or id(leaf) not in edges:
            continue
        path: list[NodeSpec] = [leaf]
        stack = [iter(edges[id(leaf)])]
        state[id(leaf)] = 1
        while stack:
            target = next(stack[-1], None)
            if target is None:
                state[id(path.pop())] = 2
                stack.pop()
                continue
            mark = state.get(id(target))
            if mark is None and id(target) not in edges:
                state[id(target)] = 2  # references nothing: no cycle through it
            elif mark == 1:
                start = next(i for i, n in enumerate(path) if n is target)
                cycle = " -> ".join(f"'{n.id}'" for n in (*path[start:], target))
                error(path[-1].location, f"reference cycle: {cycle}")
            elif mark is None:
                state[id(target)] = 1
                path.append(target)
                stack.append(iter(edges.get(id(target), ())))
