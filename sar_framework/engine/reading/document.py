"""Document: a tree file as plain values, with the YAML nodes they came from.

:func:`to_document` turns composed YAML nodes into plain values (dicts, lists, scalars)
and remembers the YAML key and value node of every path, so a problem found in the
plain values (by :mod:`.structure`'s schema check or the later checks) maps back to
``file:line:col``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from yaml.nodes import MappingNode, Node, ScalarNode, SequenceNode

from sar_framework.engine.diagnostics import SourceLocation
from sar_framework.engine.nodes.node_kinds import MAX_DEPTH
from sar_framework.engine.reading.yaml_source import Reader, location

__all__ = ["MAX_YAML_DEPTH", "DocPath", "Document", "describe", "to_document"]

#: A place in a document: the keys and list indices from its top.
DocPath = tuple[str | int, ...]
#: Deepest YAML nesting checked (a node level takes two or three YAML levels).
MAX_YAML_DEPTH = 3 * MAX_DEPTH + 10

@dataclass
class Document:
    """One tree file as plain values, with the YAML nodes they came from.

    Attributes:
        file: The file name to print.
        value: The plain value of the whole file.
        keys: Path of a mapping entry -> its key node.
        nodes: Path -> its value node.
        reported: Paths whose YAML-level problems are already reported (their value is
            None or left out); schema errors at or below them are not repeated.
        too_deep: The first node nested deeper than :data:`MAX_YAML_DEPTH`, if any (not
            converted; the schema check is skipped).
    """

    file: str
    value: Any = None
    keys: dict[DocPath, Node] = field(default_factory=dict)
    nodes: dict[DocPath, Node] = field(default_factory=dict)
    reported: set[DocPath] = field(default_factory=set)
    too_deep: Node | None = None

    def where(self, path: DocPath) -> SourceLocation:
        """Return where the value at ``path`` (or its nearest known parent) starts."""
        while path not in self.nodes and path:
            path = path[:-1]
        return location(self.nodes[path], self.file)

    def key_where(self, path: DocPath) -> SourceLocation:
        """Return where the key of the entry at ``path`` starts (else its value)."""
        key = self.keys.get(path)
        return location(key, self.file) if key is not None else self.where(path)


def to_document(root: MappingNode, reader: Reader) -> Document:
    """Convert a file's top mapping to plain values, reporting YAML-level problems.

    Args:
        root: The composed top-level mapping.
        reader: Reports duplicate keys, bad tags and bad scalars of this file.

    Returns:
        The document.
    """
    doc = Document(reader.file)
    doc.value = _plain(root, (), doc, reader)
    return doc


def _plain(node: Node, path: DocPath, doc: Document, reader: Reader) -> Any:
    doc.nodes[path] = node
    if len(path) > MAX_YAML_DEPTH:
        doc.too_deep = doc.too_deep or node
        doc.reported.add(path)
        return None
    if type(node) is ScalarNode:
        ok, value = reader.scalar(node)
        if not ok:
            doc.reported.add(path)
        return value
    if type(node) is SequenceNode:
        items = reader.sequence(node)
        if items is None:
            doc.reported.add(path)
            return None
        return [_plain(item, (*path, i), doc, reader) for i, item in enumerate(items)]
    entries = reader.items(node)  # type: ignore[arg-type]
    if entries is None:
        doc.reported.add(path)
        return None
    out = {}
    for key, key_node, value_node in entries:
        doc.keys[(*path, key)] = key_node
        out[key] = _plain(value_node, (*path, key), doc, reader)
    return out


def describe(value: Any, node: Node | None = None) -> str:
    """Say what a plain value is, for "got ..." in messages.

    Args:
        value: The value.
        node: Its YAML node (for the text of an unusual scalar such as a date).

    Returns:
        For example ``integer 3``, ``string 'yes'``, ``a list``, ``null``.
    """
    if isinstance(value, dict):
        return "a mapping"
    if isinstance(value, list):
        return "a list"
    if value is None:
        return "null"
    if isinstance(value, bool):
        return f"boolean {str(value).lower()}"
    if isinstance(value, int):
        return f"integer {value}"
    if isinstance(value, float):
        return f"number {value!r}"
    if isinstance(value, str):
        return f"string '{value}'"
    text = node.value if isinstance(node, ScalarNode) else value
    return f"a {type(value).__name__} '{text}' (quote it to make a string)"
