"""Tree files: the main file and, transitively, the files it includes, as documents.

Reading reports what keeps a file from being a tree file (YAML problems, an empty file,
a file that is not a mapping); following ``include:`` reports missing files and include
cycles. ``plugins:`` entries are collected for the registry.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from yaml.nodes import MappingNode, ScalarNode

from sar_framework.engine.diagnostics import Diagnostic, SourceLocation, display_path
from sar_framework.engine.reading import yaml_source
from sar_framework.engine.reading.document import Document, describe, to_document


def normalise(path: Path) -> Path:
    """Fold ``..`` without resolving symbolic links."""
    return Path(os.path.normpath(str(path)))


def strings(doc: Document, key: str) -> list[tuple[str, SourceLocation]]:
    """Return the string items of a top-level list (``plugins``, ``include``) and where."""
    value = doc.value.get(key)
    if not isinstance(value, list):
        return []
    return [(v, doc.where((key, i))) for i, v in enumerate(value) if isinstance(v, str)]


class TreeFiles:
    """The files of one validation run and what reading them found.

    Attributes:
        structural: File-level and YAML-level problems (the schema check adds its own).
        semantic: Include problems (the semantic walk adds its own).
        files: Every file read (absolute, normalised) -> its document, None if unreadable.
        plugin_entries: ``plugins:`` entries: (entry, its file's directory, where).
    """

    def __init__(self) -> None:
        self.structural: list[Diagnostic] = []
        self.semantic: list[Diagnostic] = []
        self.files: dict[Path, Document | None] = {}
        self.plugin_entries: list[tuple[str, Path, SourceLocation]] = []

    def error(self, where: SourceLocation, message: str) -> None:
        """Record a semantic problem."""
        self.semantic.append(Diagnostic(where, message))

    # -- files --------------------------------------------------------------------------
    def read(self, path: Path, shown: str) -> Document | None:
        """Read one file into a document; report what keeps it from being one."""
        root, problems = yaml_source.read(path, shown)
        self.structural.extend(problems)
        reader = yaml_source.Reader(shown, self.structural)
        if root is None:
            if not problems:
                self.structural.append(Diagnostic(SourceLocation(shown, 1, 1), "empty file: a "
                                       "tree file needs 'format: 1' and a 'root' node"))
            return None
        if type(root) is not MappingNode:
            value: Any = []
            if type(root) is ScalarNode:
                value = yaml_source.Reader(shown, []).scalar(root)[1]
            got = describe(value, root)
            if isinstance(value, str) and value.lstrip().startswith("<"):
                got = "BehaviorTree.CPP XML: turn it into a tree file with 'sar-tree import FILE'"
            reader.error(root, f"a tree file is a mapping (format, name, root, ...), got {got}")
            return None
        doc = to_document(root, reader)
        return doc if isinstance(doc.value, dict) else None

    def visit(self, path: Path, shown: str, stack: tuple[Path, ...]) -> None:
        """Read a file, note its plugin entries and visit its includes (depth first)."""
        doc = self.files[path] = self.read(path, shown)
        if doc is None:
            return
        for entry, where in strings(doc, "plugins"):
            self.plugin_entries.append((entry, path.parent, where))
        for entry, where in strings(doc, "include"):
            target = Path(entry).expanduser()
            target = normalise(path.parent / target if not target.is_absolute() else target)
            if target in stack or target == path:
                loop = stack[stack.index(target):] if target in stack else ()
                names = [display_path(p) for p in (*loop, path, target)]
                self.error(where, f"include cycle: {' -> '.join(names)}")
            elif target in self.files:
                continue
            elif not target.is_file():
                what = "is not a file" if target.exists() else "does not exist"
                self.error(where, f"included file '{entry}' {what}")
                self.files[target] = None
            else:
                self.visit(target, display_path(target), (*stack, path))
