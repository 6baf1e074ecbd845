"""Data edges of a diagram: which node writes the blackboard entry another reads.

Each is a dotted green edge from writer to reader, labelled with the entry; an entry that
many nodes share is drawn once, as a note of its own, so its edges stay readable.
"""

from __future__ import annotations

from collections.abc import Callable

import graphviz

from sar_framework.engine.rendering.labels import clean, data_edges
from sar_framework.engine.spec import TreeSpec

#: An entry written or read by more nodes than this gets a node of its own.
SHARED_ENTRY = 3
#: The font size of an entry's node (the size of a node's settings).
FONT_SMALL = "8"
Edge = tuple[str, str, dict[str, str]]


def _plain(text: str) -> str:
    return graphviz.escape(clean(text))


def draw_data_edges(graph: graphviz.Digraph, spec: TreeSpec,
                    node_id: Callable[[str], str]) -> tuple[list[Edge], set[str]]:
    """The dotted data edges; an entry shared by many nodes gets a node of its own.

    An entry that more than :data:`SHARED_ENTRY` nodes write or read is drawn once, as a
    small note, with one edge from each writer to it and one from it to each reader:
    ``n`` writers and ``m`` readers give ``n + m`` edges, not ``n * m`` crossing ones.

    Args:
        graph: The diagram; the entries' own nodes are added to it.
        spec: The validated tree.
        node_id: A node's uid -> its id in the diagram.

    Returns:
        The edges to draw (tail id, head id, attributes) and the ids of the entry nodes.
    """
    order = {node.uid: index for index, node in enumerate(spec.root.walk())}
    found = data_edges(spec)
    touching: dict[str, set[str]] = {}
    for writer, reader, entry in found:
        touching.setdefault(entry, set()).update((writer, reader))
    hubs: set[str] = set()
    shared = sorted(e for e, nodes in touching.items() if len(nodes) > SHARED_ENTRY)
    style = {"style": "dotted", "color": "darkgreen", "fontcolor": "darkgreen",
             "constraint": "false"}
    edges: list[Edge] = []
    for index, entry in enumerate(shared):
        hub = f"entry{index}"
        hubs.add(hub)
        graph.node(hub, label=_plain(entry), shape="note", style="filled",
                   fillcolor="honeydew", color="darkgreen", fontcolor="darkgreen",
                   fontsize=FONT_SMALL, tooltip=_plain(f"blackboard entry {entry}"))
        pairs = [(w, r) for w, r, e in found if e == entry]
        for writer in sorted({w for w, _ in pairs}, key=order.__getitem__):
            edges.append((node_id(writer), hub, style))
        for reader in sorted({r for _, r in pairs}, key=order.__getitem__):
            edges.append((hub, node_id(reader), style))
    for writer, reader, entry in found:
        if entry in shared:
            continue
        attrs = {**style, "xlabel": _plain(entry)}
        tail, head = writer, reader
        if order[writer] < order[reader]:
            # dot lays a same-rank edge's head left of its tail, which would swap
            # the children: draw it from the later node, arrow turned back
            tail, head, attrs = reader, writer, {**attrs, "dir": "back"}
        edges.append((node_id(tail), node_id(head), attrs))
    return edges, hubs
