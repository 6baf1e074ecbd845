"""Tree file -> :class:`~..spec.TreeSpec`, or every problem found, in one pass.

The files are read (:mod:`..reading`), then checked: :mod:`.structure`, :mod:`.semantics`.
Every layer collects all of its diagnostics; errors in an included file point into it.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from sar_framework.engine.checking.initial_values import override_initial
from sar_framework.engine.checking.semantics import TOO_DEEP, Semantics
from sar_framework.engine.checking.structure import StructureCheck
from sar_framework.engine.diagnostics import Diagnostic, SourceLocation
from sar_framework.engine.nodes.node_kinds import FORMAT_VERSION, MAX_DEPTH, TOP_LEVEL_ATTRS
from sar_framework.engine.reading.tree_files import TreeFiles, normalise
from sar_framework.engine.reading.yaml_source import location
from sar_framework.engine.registry import Registry, default_registry, extend
from sar_framework.engine.spec import TreeSpec

__all__ = ["FORMAT_VERSION", "MAX_DEPTH", "TOP_LEVEL_ATTRS", "ValidationResult", "validate_file"]


@dataclass
class ValidationResult:
    """What validating a tree file produced.

    Attributes:
        spec: The validated tree, or None when there were errors.
        diagnostics: Every problem found (errors and warnings), sorted by location.
        structural: The subset found reading the files and by the schema check.
        registry: The registry the tree was checked against (with its local plugins).
        library: For a file with ``subtrees`` and no ``root`` (a file meant to be
            included): how many subtrees it and its includes define; else None. Its
            subtrees are checked, but references inside them only where they are used.
        files: Every tree file read (absolute, normalised) -> its name in diagnostics;
            the main file first.
        plugin_entries: The ``plugins:`` entries of those files, with the directory each
            is relative to.
    """

    spec: TreeSpec | None
    diagnostics: list[Diagnostic]
    structural: list[Diagnostic]
    registry: Registry
    library: int | None = None
    files: dict[Path, str] = field(default_factory=dict)
    plugin_entries: list[tuple[str, Path]] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        """Whether the tree has no errors."""
        return not any(d.severity == "error" for d in self.diagnostics)


def in_order(diagnostics: list[Diagnostic]) -> list[Diagnostic]:
    """Return the diagnostics without repeats, sorted by location."""
    unique = list(dict.fromkeys(diagnostics))
    unique.sort(key=lambda d: (d.location.file, d.location.line, d.location.col))
    return unique


def main_file(path: str | Path) -> Path:
    """Return the absolute, normalised path under which a tree file is validated.

    Args:
        path: The tree file, as the user named it.

    Returns:
        The path (symbolic links are kept, ``..`` is folded).
    """
    return normalise(Path(path).absolute())


def local_registry(
    base: Registry,
    plugin_paths: Sequence[str | Path],
    plugin_entries: Sequence[tuple[str, Path, SourceLocation | None]],
) -> Registry:
    """Return ``base`` plus the plugins a load names (``base`` itself when none).

    Args:
        base: Built-ins and entry points.
        plugin_paths: Extra plugin paths given by the caller (relative to the cwd).
        plugin_entries: A tree's ``plugins:`` entries: (entry, its directory, where).

    Returns:
        The registry the tree is checked against and built with.
    """
    if not plugin_paths and not plugin_entries:
        return base
    reg = base.copy()
    for entry in plugin_paths:
        reg.import_path(str(entry), Path.cwd())
    for entry, directory, where in plugin_entries:
        reg.import_path(entry, directory, location=where)
    return extend(reg, ())


def validate_file(
    path: str | Path,
    *,
    registry: Registry | None = None,
    plugin_paths: Sequence[str | Path] = (),
    initial_values: Mapping[str, object] | None = None,
) -> ValidationResult:
    """Validate a tree file and the files it includes.

    Args:
        path: The tree file, as the user named it (diagnostics print it that way).
        registry: The plugins to check against; default: built-ins and entry points.
        plugin_paths: Extra plugin files, dirs or modules (like ``--plugin-path``).
        initial_values: Initial values of the main tree's declared entries, given from
            outside the file (``sar-tree run --set``), checked against their types.

    Returns:
        The result; ``spec`` is None when there were errors.
    """
    base = registry if registry is not None else default_registry()
    shown = str(path)
    main_path = main_file(path)
    # 1. Read the main file and, transitively, its includes.
    files = TreeFiles()
    files.visit(main_path, shown, ())
    plugin_entries = files.plugin_entries

    # 2. The registry: built-ins and entry points, plus the local plugins named.
    reg = local_registry(base, plugin_paths, plugin_entries)
    checker = Semantics(reg, files)

    # 3. The structure of every file, by jsonschema on the schema of that registry.
    structure = StructureCheck(reg)
    for doc in checker.files.values():
        if doc is not None:
            checker.structural.extend(structure.check(doc))

    # 4. The semantics, while the specs are made.
    root = checker.walk(main_path)
    for doc in checker.files.values():
        if doc is not None and doc.too_deep is not None:
            checker.error(location(doc.too_deep, doc.file), TOO_DEEP)
    main = checker.files.get(main_path)
    library = main is not None and "root" not in main.value and "subtrees" in main.value
    if main is not None and "root" not in main.value and not library:
        checker.error(SourceLocation(shown, 1, 1), "missing 'root': the node the tree starts from")

    diagnostics = in_order([*reg.diagnostics, *checker.structural, *checker.semantic])
    if any(d.message == TOO_DEEP for d in diagnostics):  # once is enough
        first = next(d for d in diagnostics if d.message == TOO_DEEP)
        diagnostics = [d for d in diagnostics if d.message != TOO_DEEP or d is first]
    spec = None
    if root is not None and not any(d.severity == "error" for d in diagnostics):
        name = main.value.get("name") if main is not None else None
        spec = TreeSpec(
            name=name if isinstance(name, str) else main_path.stem,
            description=main.value.get("description") or "" if main is not None else "",
            root=root,
            source=shown,
            plugin_paths=[plugin_path(e, d) for e, d, _ in plugin_entries],
            entries=checker.entries.entries(),
            declarations=checker.entries.scopes,
            completion=str(main.value.get("completion") or "") if main is not None else "",
        )
        section = (main.key_where(("blackboard",)) if main is not None
                   and isinstance(main.value, dict) and "blackboard" in main.value else None)
        overridden = override_initial(spec, initial_values or {}, section)
        if overridden:
            diagnostics, spec = in_order([*diagnostics, *overridden]), None
    return ValidationResult(
        spec, diagnostics, in_order(checker.structural), reg,
        len(checker.subtrees) if library else None,
        {p: d.file for p, d in checker.files.items() if d is not None},
        [(entry, directory) for entry, directory, _ in plugin_entries],
    )


def plugin_path(entry: str, directory: Path) -> str:
    """Return a ``plugins:`` entry as a path when it names one, else as written (a module).

    Args:
        entry: The entry.
        directory: The directory of the file that wrote it.

    Returns:
        What :attr:`.spec.TreeSpec.plugin_paths` holds for it.
    """
    candidate = directory / entry
    return str(candidate) if candidate.exists() else entry
