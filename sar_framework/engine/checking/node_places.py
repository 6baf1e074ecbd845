"""Words for a node that a message names: by its name, or by its place in the document.

Used by the structure check (:mod:`.structure`) when a node has no name of its own
(``selector (child 2 of the root sequence) has no children``), and the hint for a plugin
name nothing registered is close to.
"""

from __future__ import annotations

from typing import Any

DocPath = tuple[str | int, ...]

#: What an unknown plugin name with nothing close to it is told: the two routes to a leaf.
UNKNOWN_PLUGIN_HINT = (
    " (if it is a leaf of your own: install its package (an entry point in group "
    "'sar_framework.plugins'), or name its module, .py file or folder in the tree's "
    "'plugins:' key or with --plugin-path; see docs/tutorials/02_writing_a_plugin.md)")


def node_label(kind: str, path: DocPath, value: Any) -> str:
    """Name the node at ``path`` (its attributes) for a message.

    ``sequence 'Patrol'`` when it has a name; otherwise where it is: ``the root sequence``,
    ``sequence (child 2 of selector 'Mission')``, ``sequence (the child of timeout)``.

    Args:
        kind: The node's kind.
        path: The path of its attribute mapping in the document.
        value: The document's value.
    """
    def at(where: DocPath) -> Any:
        node = value
        for key in where:
            try:
                node = node[key]
            except (KeyError, IndexError, TypeError):
                return None
        return node

    attrs = at(path)
    if isinstance(attrs, dict) and isinstance(attrs.get("name"), str):
        return f"{kind} '{attrs['name']}'"
    above = path[:-1]  # the node's own mapping {kind: attrs}
    if above and above[-1] == "root":
        return f"the root {kind}"
    if len(above) >= 3 and isinstance(above[-1], int) and above[-2] == "children":
        parent = node_label(str(above[-3]), above[:-2], value)
        return f"{kind} (child {above[-1] + 1} of {parent})"
    if len(above) >= 2 and above[-1] == "child":
        return f"{kind} (the child of {node_label(str(above[-2]), above[:-1], value)})"
    return kind
