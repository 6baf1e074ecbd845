"""Draw a validated tree: Graphviz (dot/svg/png/pdf) and terminal text.

The diagram follows py_trees' own conventions (``py_trees.display.dot_tree``):
selectors are cyan octagons, sequences orange boxes, parallels gold
parallelograms, decorators ghost-white ellipses and leaves grey ellipses.
py_trees' text symbols mark the kind and the memory flag (``{-}`` sequence
with memory, ``[-]`` reactive sequence, ``{o}``/``[o]`` selectors, ``/_/``
parallel, ``-^-`` decorator, ``-->`` leaf). On top of that every node shows
its settings (memory, policies, decorator params, leaf params and ``id``);
references are dashed edges from the referencing leaf to the referenced one,
labelled with the param name; the top node of an inserted subtree gets a
double border and a ``subtree: NAME`` note. (Subtrees are not drawn as
clusters: Graphviz 2.43's dot aborts with "trouble in init_rank" on clusters
combined with the non-constraining reference edges.)

Given ``statuses`` (``NodeSpec.uid`` -> ``"SUCCESS"``, ``"FAILURE"``,
``"RUNNING"`` or ``"INVALID"``), nodes are filled by status instead of by kind
and a status legend is added under the title::

    render_to_file(spec, Path("out/tree.svg"), statuses={"0": "SUCCESS"})
    print(render_text(spec, unicode=False))

Graphviz node ids are derived from uids (``"0.1.3"`` -> ``n0_1_3``), so the
same file always gives the same DOT source.
"""

from __future__ import annotations

import html
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import graphviz

from sar_framework.engine.rendering.data_flow import draw_data_edges
from sar_framework.engine.rendering.labels import (
    UNICODE,
    clean,
    data_edges,
    info_and_params,
    insertion_ports,
    symbol,
)
from sar_framework.engine.rendering.text_tree import render_text
from sar_framework.engine.spec import Category, NodeSpec, TreeSpec

__all__ = [
    "FORMATS",
    "STATUS_COLOURS",
    "GraphvizNotFound",
    "RenderError",
    "data_edges",
    "node_id",
    "render_dot",
    "render_text",
    "render_to_file",
]

#: Output formats, by file extension.
FORMATS: dict[str, str] = {".svg": "svg", ".png": "png", ".pdf": "pdf", ".dot": "dot"}

#: Fill colour per py_trees status value.
STATUS_COLOURS: dict[str, str] = {
    "SUCCESS": "#8fd98f",
    "FAILURE": "#f28b82",
    "RUNNING": "#8ec5f5",
    "INVALID": "#d9d9d9",
}

_FONT = "Helvetica"
_FONT_SIZE = "10"
_SMALL = "8"
_MAX_PARAM_LINES = 8

# (shape, fill colour) per composite kind, as py_trees.display draws them.
_COMPOSITE_STYLE: dict[str, tuple[str, str]] = {
    "sequence": ("box", "orange"),
    "selector": ("octagon", "cyan"),
    "parallel": ("parallelogram", "gold"),
}
_DECORATOR_STYLE = ("ellipse", "ghostwhite")
_LEAF_STYLE = ("ellipse", "gray")

_DOTTED_UID = re.compile(r"[0-9]+(?:\.[0-9]+)*")


class RenderError(RuntimeError):
    """Graphviz failed to produce the requested output."""


class GraphvizNotFound(RenderError):  # noqa: N818 - name is part of the CLI contract
    """The Graphviz ``dot`` executable is not installed or not on ``PATH``."""


# --------------------------------------------------------------------------- helpers


def node_id(uid: str) -> str:
    """Return the Graphviz node id of the node with this uid.

    Dotted index paths (the loader's uids) map to readable ids, anything else
    to a hex encoding, so distinct uids always give distinct ids.

    Args:
        uid: A :attr:`NodeSpec.uid`.

    Returns:
        A DOT identifier that needs no quoting, e.g. ``n0_1_3`` for ``"0.1.3"``.
    """
    if _DOTTED_UID.fullmatch(uid):
        return "n" + uid.replace(".", "_")
    return "u" + uid.encode("utf-8", "surrogatepass").hex()


def _html(text: str) -> str:
    r"""Escape text for a Graphviz HTML-like label.

    Graphviz expands ``\N``, ``\G``... in HTML labels too (after entity
    decoding), so backslashes are doubled as well as XML-escaped. ``]`` becomes a
    character reference: Graphviz 2.43's HTML lexer rejects a bare ``]`` before a tag.
    """
    escaped = html.escape(clean(text).replace("\\", "\\\\"), quote=True)
    return escaped.replace("]", "&#93;")


def _plain(text: str) -> str:
    """Escape text for a plain (escString) Graphviz attribute such as a tooltip."""
    return graphviz.escape(clean(text))


def _normalise_statuses(statuses: Mapping[str, Any] | None) -> dict[str, str]:
    """Map uid -> upper-case status name, rejecting unknown status values.

    Accepts ``"SUCCESS"``, ``"success"``, ``"Status.SUCCESS"`` or a
    ``py_trees.common.Status`` member.
    """
    result: dict[str, str] = {}
    for uid, value in (statuses or {}).items():
        name = str(getattr(value, "value", value)).upper().removeprefix("STATUS.")
        if name not in STATUS_COLOURS:
            raise ValueError(
                f"unknown status {value!r} for node {uid!r}; "
                f"expected one of {', '.join(STATUS_COLOURS)}"
            )
        result[uid] = name
    return result


# --------------------------------------------------------------------------- DOT


def _dot_label(node: NodeSpec, status: str | None, all_params: bool) -> str:
    """Build the HTML-like label of one node.

    Lines: an optional subtree note, the name (bold), the kind and settings,
    leaf params (left-aligned, at most ``_MAX_PARAM_LINES``) and the status.
    """
    glyphs = UNICODE
    small = f'<FONT POINT-SIZE="{_SMALL}">'
    # Every line carries its own break, so the param block's left-aligned
    # breaks are not followed by an extra (empty) centred one.
    lines: list[str] = []
    if node.subtree is not None:
        lines.append(f"{small}<I>subtree: {_html(node.subtree)}</I></FONT><BR/>")
        ports = insertion_ports(node, glyphs)
        if ports:  # the values this use gives the subtree
            body = "".join(f'{_html(port)}<BR ALIGN="LEFT"/>' for port in ports)
            lines.append(f'{small}<I>{body}</I></FONT>')
    lines.append(f"<B>{_html(node.name)}</B><BR/>")
    info, params = info_and_params(node, glyphs, all_params, id_sep=": ",
                                   kind=f"{symbol(node)} {node.kind}")
    if info:
        lines.append(f"{small}{_html(', '.join(info))}</FONT><BR/>")
    if len(params) > _MAX_PARAM_LINES:
        hidden = len(params) - _MAX_PARAM_LINES + 1
        params = [*params[: _MAX_PARAM_LINES - 1], f"{glyphs.ellipsis} {hidden} more"]
    if params:
        body = "".join(f'{_html(line)}<BR ALIGN="LEFT"/>' for line in params)
        lines.append(f"{small}{body}</FONT>")
    if status is not None:
        lines.append(f"{small}<I>{status}</I></FONT>")
    return "<" + "".join(lines).removesuffix("<BR/>") + ">"


def _graph_label(spec: TreeSpec, legend: bool) -> str:
    """Build the diagram title: tree name, shortened description, status legend.

    The legend lives in the graph label rather than in a node so that it never
    takes part in (or disturbs) the tree layout.
    """
    lines = [f"<B>{_html(spec.name)}</B>"]
    description = " ".join(spec.description.split())
    if description:
        if len(description) > 120:
            description = description[:119] + "…"
        lines.append(f'<FONT POINT-SIZE="{_SMALL}">{_html(description)}</FONT>')
    if not legend:
        return "<" + "<BR/>".join(lines) + ">"
    swatches = "".join(
        f'<TD BGCOLOR="{colour}" BORDER="1" WIDTH="14"> </TD><TD ALIGN="LEFT">{status}</TD>'
        for status, colour in STATUS_COLOURS.items()
    )
    legend_table = (
        f'<FONT POINT-SIZE="{_FONT_SIZE}"><TABLE BORDER="0" CELLSPACING="3">'
        f"<TR><TD><I>status:</I></TD>{swatches}</TR></TABLE></FONT>"
    )
    rows = "".join(f"<TR><TD>{line}</TD></TR>" for line in lines)
    return (
        f'<<TABLE BORDER="0" CELLSPACING="0" CELLPADDING="1">{rows}'
        f"<TR><TD>{legend_table}</TD></TR></TABLE>>"
    )


def _style(node: NodeSpec) -> tuple[str, str]:
    """Return (shape, fill colour) for a node, by category and kind."""
    if node.category is Category.COMPOSITE:
        return _COMPOSITE_STYLE.get(node.kind, ("box", "orange"))
    if node.category is Category.DECORATOR:
        return _DECORATOR_STYLE
    return _LEAF_STYLE


def render_dot(
    spec: TreeSpec, *, statuses: Mapping[str, str] | None = None, all_params: bool = False,
    data: bool = False,
) -> str:
    """Return the Graphviz DOT source of a tree diagram.

    Args:
        spec: The validated tree.
        statuses: Optional map ``NodeSpec.uid`` -> py_trees status value
            (``"SUCCESS"``, ``"FAILURE"``, ``"RUNNING"``, ``"INVALID"``). When given,
            nodes are filled by status (nodes missing from the map count as
            ``INVALID``, i.e. never ticked) and a legend is drawn.
        all_params: Show every leaf param, defaults included (default: only those set).
        data: Also draw data edges: dotted, from a node that writes a blackboard entry
            to each node that reads it, labelled with the entry.

    Returns:
        The DOT source (a ``digraph``).

    Raises:
        ValueError: On an unknown status value or duplicate uids in ``spec``.
    """
    coloured = statuses is not None
    status_of = _normalise_statuses(statuses)
    graph = graphviz.Digraph(
        name="tree",
        graph_attr={
            "label": _graph_label(spec, legend=coloured),
            "labelloc": "t",
            "fontname": _FONT,
            # Children left to right in tick order (costs time on huge trees,
            # but a behaviour tree's meaning depends on child order).
            "ordering": "out",
            "rankdir": "TB",
            "nodesep": "0.2",
            "ranksep": "0.35",
            # Same speed as splines here, but robust: spline routing of long
            # reference edges fails ("unable to reclaim box space") on big trees.
            "splines": "polyline",
        },
        node_attr={"fontname": _FONT, "fontsize": _FONT_SIZE, "style": "filled", "margin": "0.06"},
        edge_attr={"fontname": _FONT, "fontsize": _SMALL, "arrowsize": "0.6"},
    )

    seen: set[str] = set()
    edges: list[tuple[str, str, dict[str, str]]] = []
    for node in spec.nodes():
        if node.uid in seen:
            raise ValueError(f"duplicate uid {node.uid!r} in tree {spec.name!r}")
        seen.add(node.uid)
        shape, fill = _style(node)
        status = status_of.get(node.uid, "INVALID") if coloured else None
        if status is not None:
            fill = STATUS_COLOURS[status]
        where = f"{node.kind} [{node.uid}] at {node.location}"
        if node.subtree is not None:
            where += f", from subtree {node.subtree}"
        graph.node(
            node_id(node.uid),
            label=_dot_label(node, status, all_params),
            shape=shape,
            fillcolor=fill,
            # A double border marks where a subtree was inserted.
            peripheries="2" if node.subtree is not None else None,
            tooltip=_plain(where),
        )
        edges.extend((node_id(node.uid), node_id(c.uid), {}) for c in node.children)
        for param, target in node.refs.items():
            attrs = {
                "style": "dashed",
                "color": "steelblue",
                "fontcolor": "steelblue",
                # xlabel, not label: an edge label makes dot double every rank
                # for label nodes, ~4x slower layout at 2,000 nodes.
                "xlabel": _plain(param),
                "constraint": "false",
            }
            edges.append((node_id(node.uid), node_id(target.uid), attrs))

    hubs: set[str] = set()
    if data:
        data_flow, hubs = draw_data_edges(graph, spec, node_id)
        edges.extend(data_flow)
    # A reference to a node outside the tree (never in a validated tree) keeps
    # its label text but gets no edge, rather than a stray node.
    known = {node_id(uid) for uid in seen} | hubs
    for tail, head, attrs in edges:
        if head in known:
            graph.edge(tail, head, **attrs)
    return graph.source


# --------------------------------------------------------------------------- files


def render_to_file(
    spec: TreeSpec,
    out: Path,
    *,
    statuses: Mapping[str, str] | None = None,
    all_params: bool = False,
    data: bool = False,
) -> Path:
    """Render a tree diagram to a file; the format follows the extension.

    Args:
        spec: The validated tree.
        out: Target file ending in ``.svg``, ``.png``, ``.pdf`` or ``.dot``;
            parent directories are created.
        statuses: Optional uid -> status map, see :func:`render_dot`.
        data: Draw data edges (writer -> reader of each entry), see :func:`render_dot`.
        all_params: Show every leaf param, defaults included (default: only those set).

    Returns:
        ``out``.

    Raises:
        ValueError: On an unsupported extension or an unknown status value.
        GraphvizNotFound: When ``dot`` is needed (svg/png/pdf) but not installed.
        RenderError: When ``dot`` fails.
    """
    out = Path(out)
    fmt = FORMATS.get(out.suffix.lower())
    if fmt is None:
        raise ValueError(
            f"cannot render to {str(out)!r}: unsupported extension {out.suffix or '(none)'!r}; "
            f"use one of {', '.join(FORMATS)}"
        )
    source = render_dot(spec, statuses=statuses, all_params=all_params, data=data)
    out.parent.mkdir(parents=True, exist_ok=True)
    if fmt == "dot":
        out.write_text(source, encoding="utf-8")
        return out
    try:
        data = graphviz.pipe("dot", fmt, source.encode("utf-8"), quiet=True)
    except graphviz.ExecutableNotFound as exc:
        raise GraphvizNotFound(
            f"cannot render {out.name}: the Graphviz 'dot' program was not found on PATH; "
            "install Graphviz (e.g. 'sudo apt install graphviz') or render to .dot instead"
        ) from exc
    except graphviz.CalledProcessError as exc:
        stderr = exc.stderr.decode("utf-8", "replace") if isinstance(exc.stderr, bytes) else ""
        head = "\n".join(stderr.strip().splitlines()[:5])
        raise RenderError(f"Graphviz 'dot' failed rendering {out.name}:\n{head}") from exc
    out.write_bytes(data)
    return out


