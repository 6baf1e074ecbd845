"""The tree's blackboard entries as the live views show them: changes per tick, as text.

:class:`EntryTracker` reads the values of a loaded tree's entries (``LoadedTree.entries``)
from the py_trees blackboard after a tick and returns those whose text changed since it was
last asked, as ``[name, key, value text, type, writer]`` rows; ``full=True`` returns every
entry (the first message, a late joiner). A tree without entries costs one length test.

Values are rendered by :func:`value_text`: never ``repr`` of an unknown object (which may
be huge or raise), bounded to :data:`TEXT_MAX` characters; ROS messages compactly as
``Type@frame(field=(x=1, ...), ...)`` (nested messages without their type, a header as
its frame id) without importing ROS (a message class is recognised by its
``get_fields_and_field_types``). :func:`apply_entries` folds such rows into the current
values, for the watcher and for replay.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any

import py_trees

from sar_framework.engine.message_literals import MessageLiteral

#: Longest value text, in characters (longer ones end with ``…``).
TEXT_MAX = 100
#: How deep nested messages and containers are shown before ``…``.
DEPTH_MAX = 3
#: Items of a sequence shown before ``…``.
ITEMS_MAX = 4
#: The text of an entry not set yet.
UNSET = "-"
#: The name of the client that writes a tree's initial values (``engine/building/port_values.py``).
INITIAL_WRITER = "initial values"
_SCALARS = (bool, int, float, str, bytes, type(None))


def type_text(value: Any) -> str:
    """The type of ``value`` as a port type names it (``int``, ``geometry_msgs/msg/Pose``)."""
    cls = type(value)
    if cls is MessageLiteral:  # a literal from the tree file, not built into a message yet
        return value.type
    if hasattr(cls, "get_fields_and_field_types"):
        package = cls.__module__.split(".", 1)[0]
        return f"{package}/msg/{cls.__name__}"
    return cls.__name__


def _text(value: Any, depth: int) -> str:
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, _SCALARS):
        return repr(value if not isinstance(value, (str, bytes)) else value[:TEXT_MAX + 1])
    if depth >= DEPTH_MAX:
        return "…"
    if isinstance(value, MessageLiteral):
        return f"{value.type.rpartition('/')[2]}{_text(value.fields, depth)}"
    fields = getattr(type(value), "get_fields_and_field_types", None)
    if fields is not None:
        names = list(fields())
        frame = ""
        if "header" in names:  # its frame beside the type, the stamp left out
            names.remove("header")
            frame = f"@{getattr(value.header, 'frame_id', '')}"
        inner = ", ".join(f"{name}={_text(getattr(value, name, None), depth + 1)}"
                          for name in names)
        return f"{type(value).__name__ if depth == 0 else ''}{frame}({inner})"
    if isinstance(value, Mapping):
        items = list(value.items())
        inner = ", ".join(f"{_text(k, depth + 1)}: {_text(v, depth + 1)}"
                          for k, v in items[:ITEMS_MAX])
        return "{" + inner + (", …" if len(items) > ITEMS_MAX else "") + "}"
    if isinstance(value, (list, tuple)) or type(value).__name__ in ("ndarray", "array"):
        items = list(value[:ITEMS_MAX + 1])
        inner = ", ".join(_text(v, depth + 1) for v in items[:ITEMS_MAX])
        more = f", … ({len(value)} items)" if len(items) > ITEMS_MAX else ""
        opening, closing = ("(", ")") if isinstance(value, tuple) else ("[", "]")
        return f"{opening}{inner}{more}{closing}"
    return f"<{type(value).__name__}>"


def value_text(value: Any, limit: int = TEXT_MAX) -> str:
    """``value`` as short, safe text: scalars as Python writes them, messages compactly.

    Args:
        value: Any blackboard value.
        limit: Longest text returned.

    Returns:
        At most ``limit`` characters; ``<Type: unprintable>`` when rendering raised.
    """
    try:
        text = _text(value, 0)
    except Exception:  # a value's own accessors may raise; the view must not
        text = f"<{type(value).__name__}: unprintable>"
    return text if len(text) <= limit else text[:limit - 1] + "…"


def writers_of(keys: Iterable[str]) -> dict[str, str]:
    """``absolute key -> names of the clients that may write it``, from py_trees' metadata.

    A port's or a script's client is named after its behaviour; the builder's client that
    writes the initial values (:data:`INITIAL_WRITER`) is not a writer shown.

    Args:
        keys: The absolute keys of the entries.
    """
    names = py_trees.blackboard.Blackboard.clients
    metadata = py_trees.blackboard.Blackboard.metadata
    writers: dict[str, str] = {}
    for key in keys:
        meta = metadata.get(key)
        if meta is None:
            continue
        found = sorted({names[uuid] for uuid in (*meta.write, *meta.exclusive)
                        if uuid in names and names[uuid] != INITIAL_WRITER})
        if found:
            writers[key] = ", ".join(found)
    return writers


class EntryTracker:
    """Which entries changed since the last look, as rows for the status topic.

    Args:
        entries: ``name -> absolute key`` (``LoadedTree.entries``).
        writers: ``absolute key -> writer names`` (:func:`writers_of`); empty when unknown.
    """

    def __init__(self, entries: Mapping[str, str], writers: Mapping[str, str] | None = None
                 ) -> None:
        self._entries = sorted(entries.items())
        self._writers = dict(writers or {})
        self._last: dict[str, tuple[str, str]] = {}

    def __len__(self) -> int:
        return len(self._entries)

    def changes(self, *, full: bool = False) -> list[list[str]]:
        """Rows ``[name, key, text, type, writer]`` of the entries whose text changed.

        Args:
            full: Every entry, changed or not.
        """
        if not self._entries:
            return []
        rows = []
        for name, key in self._entries:
            shown = _shown(key)
            if full or self._last.get(key) != shown:
                self._last[key] = shown
                rows.append([name, key, shown[0], shown[1], self._writers.get(key, "")])
        return rows

    def final(self) -> dict[str, dict[str, str]]:
        """``name -> {"key", "value", "type", "writer"}`` as they stand now (``status.json``)."""
        final = {}
        for name, key in self._entries:
            value, type_ = _shown(key)
            final[name] = {"key": key, "value": value, "type": type_,
                           "writer": self._writers.get(key, "")}
        return final


def _shown(key: str) -> tuple[str, str]:
    """The text and type of the value at ``key`` on the blackboard, or the unset mark."""
    storage = py_trees.blackboard.Blackboard.storage
    if key not in storage:
        return UNSET, "unset"
    value = storage[key]
    return value_text(value), type_text(value)


ENTRY_FIELDS = ("name", "key", "value", "type", "writer")


def apply_entries(current: dict[str, dict[str, str]], rows: Iterable[Iterable[str]], *,
                  full: bool = False) -> dict[str, dict[str, str]]:
    """Fold a status message's entry rows into the values known so far.

    Args:
        current: ``name -> {"key", "value", "type", "writer"}`` (not changed).
        rows: The message's ``entries`` rows.
        full: The rows are every entry (those not listed are gone).

    Returns:
        The new ``name -> entry`` mapping, sorted by name.
    """
    merged = {} if full else dict(current)
    for row in rows:
        entry = dict(zip(ENTRY_FIELDS, row, strict=False))
        merged[entry["name"]] = entry
    return dict(sorted(merged.items()))
