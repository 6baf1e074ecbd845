"""The tree as the studio draws it: an SVG whose nodes the page colours, and each node's facts.

With a validated tree (:class:`~sar_framework.engine.spec.TreeSpec`) the SVG is the
project's own diagram (:func:`~sar_framework.engine.rendering.render.render_dot`, drawn by Graphviz
``dot``) and each node carries its params, ports and source location. Without one (a live
mission whose tree file the studio was not given) the diagram is drawn from the nodes a
status message lists (uid, name, kind) and the facts are those three.

Either way a node's Graphviz name is :func:`~sar_framework.engine.rendering.render.node_id` of its
uid (``n0_1_3``), the ``<title>`` of its SVG group, which is how the page finds it.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import graphviz

from sar_framework.engine.rendering.render import STATUS_COLOURS, node_id, render_dot

if TYPE_CHECKING:
    from sar_framework.engine.spec import NodeSpec, TreeSpec

_COMPOSITES = {"sequence": "box", "selector": "octagon", "parallel": "parallelogram"}


def _svg(source: str) -> str:
    """Lay out DOT ``source`` as SVG text without the XML prologue (for ``innerHTML``)."""
    text = graphviz.pipe("dot", "svg", source.encode("utf-8"), quiet=True).decode("utf-8")
    return text[text.find("<svg"):]


def _plain(value: Any) -> Any:
    """``value`` as JSON can hold it (anything else as its text)."""
    return json.loads(json.dumps(value, default=str))


def _facts(node: NodeSpec) -> dict[str, Any]:
    return {"uid": node.uid, "name": node.name, "kind": node.kind,
            "category": node.category.value, "id": node.id,
            "location": str(node.location), "subtree": node.subtree,
            "params": _plain(node.attrs), "ports": _plain(node.ports),
            "refs": {param: target.uid for param, target in node.refs.items()}}


def tree_view(spec: TreeSpec) -> dict[str, Any]:
    """The page's tree from a validated tree: ``{"name", "svg", "nodes": {uid: facts}}``.

    Raises:
        graphviz.ExecutableNotFound: Graphviz ``dot`` is not installed.
    """
    source = render_dot(spec)  # filled by kind; the page fills each node by its status
    return {"name": spec.name, "svg": _svg(source), "source": "file",
            "nodes": {node.uid: _facts(node) for node in spec.nodes()},
            "colours": STATUS_COLOURS}


def file_tree_view(path: str, plugin_paths: Sequence[str] = ()) -> dict[str, Any] | None:
    """The page's tree from a tree file, or None when the file does not validate."""
    from sar_framework.engine.api import validate

    result = validate(path, plugin_paths=list(plugin_paths))
    return tree_view(result.spec) if result.spec is not None else None


def status_tree_view(name: str, nodes: Sequence[dict[str, Any]]) -> dict[str, Any]:
    """The page's tree drawn from a status message's node list alone.

    Args:
        name: The tree's name.
        nodes: ``decode_status``'s node dicts (``uid``, ``name``, ``kind``), depth first.
    """
    graph = graphviz.Digraph(name="tree", graph_attr={
        "ordering": "out", "rankdir": "TB", "nodesep": "0.2", "ranksep": "0.35",
        "label": name, "labelloc": "t", "fontname": "Helvetica"},
        node_attr={"fontname": "Helvetica", "fontsize": "10", "style": "filled",
                   "margin": "0.06"})
    for node in nodes:
        uid = node["uid"]
        graph.node(node_id(uid), label=f"{node['name']}\n[{node['kind']}]",
                   shape=_COMPOSITES.get(node["kind"], "ellipse"),
                   fillcolor=STATUS_COLOURS["INVALID"])
        if "." in uid:
            graph.edge(node_id(uid.rsplit(".", 1)[0]), node_id(uid))
    return {"name": name, "svg": _svg(graph.source), "source": "status",
            "nodes": {n["uid"]: {"uid": n["uid"], "name": n["name"], "kind": n["kind"]}
                      for n in nodes},
            "colours": STATUS_COLOURS}


def matches(view: dict[str, Any], nodes: Sequence[dict[str, Any]]) -> bool:
    """Whether a tree view has exactly the nodes (uids and names) a status message lists."""
    return {uid: facts["name"] for uid, facts in view["nodes"].items()} == \
        {n["uid"]: n["name"] for n in nodes}
