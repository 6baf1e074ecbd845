"""Subtree definitions: what a ``subtrees:`` entry holds, its copies, its recursion.

The semantic walk (:mod:`.semantics`) makes each definition's spec once; every
``subtree:`` use in the main tree then inserts a fresh copy (:func:`copy_spec`) in a
scope of its own. Recursion is reported where it is expanded, and, for definitions no
tree uses, by :func:`report_cycles`.
"""

from __future__ import annotations

from dataclasses import dataclass

from sar_framework.engine.checking.entries import Report
from sar_framework.engine.diagnostics import SourceLocation
from sar_framework.engine.nodes.node_kinds import SUBTREE
from sar_framework.engine.ports import Port
from sar_framework.engine.spec import Declared, NodeSpec


@dataclass
class Subtree:
    """A named subtree definition (with its declared ports and entries, if any)."""

    name: str
    node: NodeSpec | None
    location: SourceLocation
    ports: dict[str, Port] | None = None
    local: dict[str, Declared] | None = None


def cycle_text(chain: tuple[str, ...], name: str) -> str:
    """The message of a recursion: ``recursive subtree: a -> b -> a``."""
    return "recursive subtree: " + " -> ".join((*chain[chain.index(name):], name))


def report_cycles(node: NodeSpec | None, chain: tuple[str, ...], done: set[str],
                  subtrees: dict[str, Subtree], report: Report) -> None:
    """Report recursion in a subtree definition no tree uses (a used one is expanded).

    Args:
        node: The node to look below.
        chain: The subtree names entered so far.
        done: Names already looked into (updated).
        subtrees: Every definition, by name.
        report: Where problems go.
    """
    if node is None:
        return
    if node.kind != SUBTREE:
        for child in node.children:
            report_cycles(child, chain, done, subtrees, report)
        return
    name = node.name
    if name in chain:
        report(node.location, cycle_text(chain, name))
    elif name not in done and name in subtrees:
        report_cycles(subtrees[name].node, (*chain, name), done, subtrees, report)
        done.add(name)


def copy_spec(node: NodeSpec) -> NodeSpec:
    """Return a fresh copy of a subtree definition's spec (uids, refs, bindings cleared)."""
    return NodeSpec(node.kind, node.category, node.name, "", node.location, dict(node.attrs),
                    [copy_spec(c) for c in node.children], node.id, {}, node.subtree,
                    node.written, node.ports, {}, node.scripts, symbol=node.symbol)
