"""Data flow of a tree: which node writes a blackboard entry that another node reads.

The diagram (:mod:`.render`) draws these as dotted edges when asked to::

    for writer, reader, entry in data_edges(spec):
        ...
"""

from __future__ import annotations

from sar_framework.engine.spec import TreeSpec

__all__ = ["data_edges"]


def data_edges(spec: TreeSpec) -> list[tuple[str, str, str]]:
    """Return ``(writer uid, reader uid, entry)`` for every entry a node writes and one reads.

    A node's ports and its scripts both count.

    Args:
        spec: The validated tree.

    Returns:
        One edge per writer, reader and entry (a node reading its own write is left out).
    """
    writers: dict[str, list[str]] = {}
    readers: dict[str, list[str]] = {}
    for node in spec.nodes():
        reads: set[str] = set()
        writes: set[str] = set()
        for binding in node.bindings.values():
            if binding.key is not None and binding.port.direction.writes:
                writes.add(binding.key)
            if binding.key is not None and binding.port.direction.reads:
                reads.add(binding.key)
        for script in node.scripts.values():
            writes.update(node.script_keys[n] for n in script.writes if node.script_keys.get(n))
            reads.update(node.script_keys[n] for n in script.reads if node.script_keys.get(n))
        for key in sorted(writes):
            writers.setdefault(key, []).append(node.uid)
        for key in sorted(reads):
            readers.setdefault(key, []).append(node.uid)
    return [(w, r, key[1:]) for key, ws in writers.items() for w in ws
            for r in readers.get(key, ()) if r != w]
