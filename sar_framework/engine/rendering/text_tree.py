"""The terminal drawing of a validated tree (``sar-tree render --format ascii|unicode``)."""

from __future__ import annotations

from collections.abc import Callable

from sar_framework.engine.rendering.labels import (
    ASCII,
    UNICODE,
    Glyphs,
    clean,
    info_and_params,
    insertion_ports,
    symbol,
)
from sar_framework.engine.spec import NodeSpec, TreeSpec


def text_line(
    node: NodeSpec, glyphs: Glyphs, to_text: Callable[[str], str], all_params: bool
) -> str:
    """Build one line of the text tree for ``node`` (without the tree glyphs)."""
    info, params = info_and_params(node, glyphs, all_params, id_sep="=", kind=node.kind)
    line = f"{symbol(node)} {clean(node.name)}"
    if info:
        line += f" [{', '.join(info)}]"
    if params:
        line += " " + ", ".join(params)
    if node.subtree is not None:
        ports = "".join(f", {port}" for port in insertion_ports(node, glyphs))
        line += f" {glyphs.subtree_open}subtree: {node.subtree}{ports}{glyphs.subtree_close}"
    return to_text(clean(line))


def render_text(spec: TreeSpec, *, unicode: bool = True, all_params: bool = False) -> str:
    """Return a text drawing of the tree for a terminal.

    Each line shows py_trees' kind symbol, the node name and, in brackets, the
    kind and its settings (memory flag, parallel policy, decorator params);
    leaves show their plugin (when it differs from the name), ``id`` and params,
    references as ``param -> id``::

        {-} Mission [sequence, memory]
        |-- -^- Once [one_shot, on_completion]
        |   `-- --> Setup [LoadShelves, id=setup] file="shelves.yaml"
        `-- --> Scan [ScanShelf, id=scan] shelf="A"

    Args:
        spec: The validated tree.
        unicode: Draw with Unicode box-drawing characters; ``False`` gives pure
            ASCII (non-ASCII characters in names and values are escaped).
        all_params: Show every leaf param, defaults included (default: only those set).

    Returns:
        The drawing, one node per line, ending with a newline.
    """
    glyphs = UNICODE if unicode else ASCII

    def to_text(text: str) -> str:
        return text if unicode else text.encode("ascii", "backslashreplace").decode("ascii")

    lines: list[str] = []
    # (node, prefix for its own line, prefix for its children's lines)
    stack: list[tuple[NodeSpec, str, str]] = [(spec.root, "", "")]
    while stack:
        node, own, below = stack.pop()
        lines.append(own + text_line(node, glyphs, to_text, all_params))
        last = len(node.children) - 1
        for index in range(last, -1, -1):
            is_last = index == last
            stack.append(
                (
                    node.children[index],
                    below + (glyphs.corner if is_last else glyphs.tee),
                    below + ("    " if is_last else glyphs.pipe),
                )
            )
    return "\n".join(lines) + "\n"
