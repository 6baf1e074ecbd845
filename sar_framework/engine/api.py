"""The engine's Python API: ``validate``, ``load_spec`` and ``load_tree``.

::

    from sar_framework import load_tree
    tree = load_tree("patrol.yaml", context={"inventory": inventory})
    tree.root          # the py_trees root behaviour
    tree.spec          # the validated TreeSpec
    tree.behaviours    # NodeSpec.uid -> behaviour
    tree.entries       # blackboard entry name -> absolute py_trees key
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from sar_framework.engine.checking.validate import ValidationResult
from sar_framework.engine.checking.validate import validate_file as validate
from sar_framework.engine.diagnostics import Diagnostic, SourceLocation, TreeLoadError
from sar_framework.engine.registry import Registry
from sar_framework.engine.spec import TreeSpec

if TYPE_CHECKING:
    import py_trees

__all__ = ["LoadedTree", "TreeLoadError", "load_error", "load_spec", "load_tree", "validate"]


@dataclass
class LoadedTree:
    """A tree file turned into py_trees behaviours.

    Attributes:
        root: The root behaviour (plain py_trees objects all the way down).
        spec: The validated tree the behaviours were built from.
        behaviours: ``NodeSpec.uid -> behaviour``, for every node.
        registry: The plugins the tree was checked against.
        initial_values: The initial values given from outside the file (``--set``), kept
            for a hot swap's new file.
    """

    root: py_trees.behaviour.Behaviour
    spec: TreeSpec
    behaviours: dict[str, py_trees.behaviour.Behaviour] = field(default_factory=dict)
    registry: Registry | None = None
    initial_values: dict[str, Any] = field(default_factory=dict)

    @property
    def entries(self) -> dict[str, str]:
        """Each blackboard entry of the tree by name (``goal``, ``Follow@0_2/path``) -> its key.

        The details (type, initial value, description) are in ``spec.entries``.
        """
        return {entry.name: key for key, entry in self.spec.entries.items()}


def load_error(path: str | Path, result: ValidationResult) -> TreeLoadError:
    """The error for a file that gave no tree: its diagnostics, or a missing root."""
    if result.library is not None and result.ok:
        where = SourceLocation(str(path), 1, 1)
        return TreeLoadError([Diagnostic(where, "missing 'root': this file only defines "
                                                "subtrees; include it from a tree file")])
    return TreeLoadError(result.diagnostics)


def _validated(path: str | Path, registry: Registry | None,
               plugin_paths: Sequence[str | Path],
               initial_values: Mapping[str, Any] | None = None) -> tuple[TreeSpec, Registry]:
    """The validated tree and its registry; raises when there is no tree to build."""
    result = validate(path, registry=registry, plugin_paths=plugin_paths,
                      initial_values=initial_values)
    if result.spec is not None:
        return result.spec, result.registry
    raise load_error(path, result)


def load_spec(
    path: str | Path,
    *,
    registry: Registry | None = None,
    plugin_paths: Sequence[str | Path] = (),
) -> TreeSpec:
    """Read and validate a tree file.

    Args:
        path: The tree file.
        registry: The plugins to check against; default: built-ins and entry points.
        plugin_paths: Extra plugin files, dirs or modules.

    Returns:
        The validated tree.

    Raises:
        TreeLoadError: With every problem found.
    """
    return _validated(path, registry, plugin_paths)[0]


def load_tree(
    path: str | Path,
    context: Mapping[str, Any] | None = None,
    *,
    registry: Registry | None = None,
    plugin_paths: Sequence[str | Path] = (),
    initial_values: Mapping[str, Any] | None = None,
) -> LoadedTree:
    """Read, validate and build a tree file.

    Args:
        path: The tree file.
        context: Shared objects plugins declared they need (e.g. an app's ``inventory``).
        registry: The plugins to check against; default: built-ins and entry points.
        plugin_paths: Extra plugin files, dirs or modules.
        initial_values: Initial values of the main tree's declared entries that replace
            the file's (``sar-tree run --set``), converted to their declared types.

    Returns:
        The built tree.

    Raises:
        TreeLoadError: With every problem found (validation, a missing context
            object, a plugin constructor that raised).
    """
    spec, used = _validated(path, registry, plugin_paths, initial_values)
    from sar_framework.engine.building.build import build  # py_trees' composites: only to build

    root, behaviours = build(spec, used, context)
    return LoadedTree(root, spec, behaviours, used, dict(initial_values or {}))
