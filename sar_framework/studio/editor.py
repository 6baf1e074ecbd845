"""The studio's tree editor: check a text as ``sar-tree validate`` would, complete, save.

:class:`TreeEditor` edits one tree file. :meth:`TreeEditor.check` validates a text the
page holds with the project's own validator, as if it were the file: it is written to a
hidden file beside the original (so ``include:`` and ``plugins:`` paths resolve as they
will), validated, and removed; the diagnostics name the original file, so they read exactly
as ``sar-tree validate FILE`` prints them. A valid text also gives the redrawn diagram
(:func:`~sar_framework.studio.tree_view.tree_view`). :meth:`TreeEditor.completions` lists
what the tree format accepts, read from the JSON Schema the registry generates (the
schema ``sar-tree schema`` prints): every node kind with its description and params.
:meth:`TreeEditor.save` writes the file (the server asks for the session token first), if
it lies under the directories open to the studio.

No ROS here.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from sar_framework.studio.safety import MESSAGE_MAX_BYTES, RefusedError, confine
from sar_framework.studio.tree_view import tree_view

#: The schema's definitions of node kinds: composites and decorators, and leaf plugins.
KIND_PREFIXES = ("kind.", "plugin.")
#: The hidden file a text is checked as, beside the tree file.
CHECK_PREFIX = ".studio-check-"


class TreeEditor:
    """Edits one tree file.

    Args:
        path: The tree file (it need not exist yet).
        roots: The directories the studio may write in.
        plugin_paths: Extra plugin folders, as ``--plugin-path``.
    """

    def __init__(self, path: Path, roots: Sequence[Path],
                 plugin_paths: Sequence[str] = ()) -> None:
        self.path = confine(path, roots)
        self.shown = str(path)
        self._roots = list(roots)
        self._plugin_paths = list(plugin_paths)

    def text(self) -> str:
        """The file's text now ("" for a file not written yet)."""
        try:
            return self.path.read_text(encoding="utf-8")
        except FileNotFoundError:
            return ""

    def completions(self) -> dict[str, Any]:
        """What the format accepts, from its JSON Schema.

        Returns:
            ``{"top": [keys of a tree file], "kinds": {kind: {"description", "params":
            {name: description}}}}``.
        """
        from sar_framework.engine.checking.schema import tree_schema
        from sar_framework.engine.registry import default_registry, extend

        schema = tree_schema(extend(default_registry().copy(), self._plugin_paths))
        kinds = {}
        for name, definition in schema.get("$defs", {}).items():
            prefix, _, kind = name.partition(".")
            if f"{prefix}." not in KIND_PREFIXES:
                continue
            properties = definition.get("properties", {})
            kinds[kind] = {
                "description": definition.get("description", ""),
                "params": {key: value.get("description", "")
                           for key, value in properties.items()}}
        return {"top": sorted(schema.get("properties", {})), "kinds": kinds}

    def check(self, text: str) -> dict[str, Any]:
        """Validate ``text`` as this file.

        Returns:
            ``{"type": "checked", "ok", "diagnostics": [{"line", "col", "severity",
            "message", "text"}], "tree": the diagram or None}``; ``text`` is the line
            ``sar-tree validate`` prints.
        """
        from sar_framework.engine.api import validate

        folder = self.path.parent
        if not folder.is_dir():
            raise RefusedError(f"{folder}: no such directory")
        handle, name = tempfile.mkstemp(prefix=CHECK_PREFIX, suffix=self.path.suffix,
                                        dir=folder)
        try:
            with os.fdopen(handle, "w", encoding="utf-8") as stream:
                stream.write(text)
            result = validate(name, plugin_paths=self._plugin_paths)
        finally:
            with contextlib.suppress(OSError):
                os.unlink(name)
        diagnostics = []
        for diagnostic in result.diagnostics:
            where = diagnostic.location
            file = self.shown if where.file == name else where.file
            message = diagnostic.message.replace(name, self.shown)
            line = f"{file}:{where.line}:{where.col}: {diagnostic.severity}: {message}"
            diagnostics.append({"file": file, "line": where.line, "col": where.col,
                                "severity": diagnostic.severity, "message": message,
                                "text": line})
        tree = None
        if result.spec is not None:
            try:
                tree = tree_view(result.spec)
            except Exception as err:  # Graphviz missing or failing: the check still stands
                diagnostics.append({"file": self.shown, "line": 1, "col": 1,
                                    "severity": "note", "message": f"not drawn: {err}",
                                    "text": f"{self.shown}: note: not drawn: {err}"})
        return {"type": "checked", "ok": result.spec is not None,
                "diagnostics": diagnostics, "tree": tree}

    def save(self, text: str) -> dict[str, Any]:
        """Write ``text`` to the file (confined to the roots); return its check.

        Raises:
            RefusedError: Too long, or the file lies outside the roots.
        """
        if len(text.encode("utf-8")) > MESSAGE_MAX_BYTES:
            raise RefusedError(f"a tree of more than {MESSAGE_MAX_BYTES} bytes")
        path = confine(self.path, self._roots)
        path.write_text(text, encoding="utf-8")
        return {**self.check(text), "saved": str(path)}
