"""The quick path of :func:`~.validate.validate_file`: an ordinary, valid tree, fast.

Most loads are of a tree that is valid and plainly written, in the YAML subset
:mod:`.quick_yaml` reads (with its included files, subtrees and local plugins). For such a
file this module produces the same :class:`~.validate.ValidationResult` as the
reference path (PyYAML's composer, then the full check), in about a third of the time,
by walking plain values instead of YAML nodes.

It only ever says yes. Whatever it does not recognise, and every problem (an unknown
key, a wrong type, a value out of range, a missing attribute, a dangling reference,
...), makes it give up, and the reference path runs from the start: every diagnostic
comes from there. The checks it does are those of the reference walk
(:meth:`_Checker.node <.validate._Checker.node>`) on the success path, and the
semantic steps (ids, references, ``selected``) are the reference's own methods.
``tests/engine/test_quick_validate.py`` proves the two paths agree: the same result
on every tree of the repository and on generated and mutated ones, and never a
result where the reference finds a problem.
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from sar_framework.engine import quick_yaml, validate, yaml_source
from sar_framework.engine.diagnostics import display_path
from sar_framework.engine.node_kinds import SUBTREE, Attr, AttrType
from sar_framework.engine.registry import Registry
from sar_framework.engine.spec import Category, NodeSpec, TreeSpec

_TOP_LEVEL = validate.TOP_LEVEL
_TOP_LEVEL_KEYS = frozenset(_TOP_LEVEL)
_NODE = AttrType.NODE
_NODES = AttrType.NODES
_STRING = AttrType.STRING
_STRINGS = AttrType.STRINGS
_BOOLEAN = AttrType.BOOLEAN
_INTEGER = AttrType.INTEGER
_NUMBER = AttrType.NUMBER
_LEAF = Category.LEAF
_MAX_DEPTH = validate.MAX_DEPTH
_new_location = yaml_source.new_location


class _NotOrdinaryError(Exception):
    """Not an ordinary valid tree: the reference path decides."""


def quick_validate(
    main_path: Path, shown: str, base: Registry, plugin_paths: Sequence[str | Path] = ()
) -> tuple[validate.ValidationResult, list[tuple[Path, bytes]]] | None:
    """Validate an ordinary tree file (and the files it includes) quickly, or give up.

    Args:
        main_path: The file (absolute, normalised, as :func:`~.validate.main_file`).
        shown: Its name in diagnostics and in the spec's ``source``.
        base: Built-ins and entry points.
        plugin_paths: Extra plugin files, dirs or modules (like ``--plugin-path``).

    Returns:
        The result (with no diagnostics) and each file read with its exact bytes, in
        the order read; None when the tree is not ordinary and valid (the caller then
        takes the reference path).
    """
    files = _Files()
    try:
        files.visit(main_path, shown, ())
        # Plugin files are imported once per process (Registry.import_file), so giving
        # up after this costs the reference path nothing.
        registry = validate.local_registry(
            base, plugin_paths, [(entry, directory, None) for entry, directory in files.plugins]
        )
        if registry.diagnostics:
            return None  # the reference result carries them
        spec = _Walk(registry).tree(files, main_path)
    except _NotOrdinaryError:
        return None
    spec.plugin_paths = [validate.plugin_path(entry, directory)
                         for entry, directory in files.plugins]
    result = validate.ValidationResult(
        spec, [], [], registry, None, {path: name for path, (name, _) in files.documents.items()},
        list(files.plugins),
    )
    return result, files.reads


class _Files:
    """The main file and its includes, read in the reference's order (depth first)."""

    def __init__(self) -> None:
        self.documents: dict[Path, tuple[str, quick_yaml.Mapping]] = {}
        self.reads: list[tuple[Path, bytes]] = []
        self.plugins: list[tuple[str, Path]] = []

    def visit(self, path: Path, shown: str, stack: tuple[Path, ...]) -> None:
        """Read one file, note its plugins, visit its includes (as ``_Checker.visit``)."""
        try:
            with path.open("rb") as stream:
                data = stream.read(yaml_source.MAX_FILE_BYTES + 1)
            text = data.decode("utf-8-sig")
        except (OSError, UnicodeDecodeError) as exc:
            raise _NotOrdinaryError from exc
        document = quick_yaml.parse(text) if len(data) <= yaml_source.MAX_FILE_BYTES else None
        if document is None or not _TOP_LEVEL_KEYS.issuperset(document):
            raise _NotOrdinaryError
        self.reads.append((path, data))
        self.documents[path] = (shown, document)
        for entry in _checked(_TOP_LEVEL["plugins"], document.get("plugins", [])):
            self.plugins.append((entry, path.parent))
        for entry in _checked(_TOP_LEVEL["include"], document.get("include", [])):
            target = Path(entry).expanduser()
            target = (path.parent / target) if not target.is_absolute() else target
            target = Path(os.path.normpath(str(target)))
            if target in stack or target == path or not target.is_file():
                raise _NotOrdinaryError  # an include cycle, or no such file
            if target not in self.documents:
                self.visit(target, display_path(target), (*stack, path))


class _Walk:
    """One quick walk: the reference checker's state, fed from plain values."""

    def __init__(self, registry: Registry) -> None:
        self.checker = validate._Checker(registry)
        self.registry = registry
        self.file = ""
        self.decls = dict(validate._KIND_DECLS)  # plus each plugin met, on first use
        # Subtree name -> (its node as plain values, its file's name); walked afresh at
        # each use in the tree (a fresh copy), or once on its own when never used.
        self.definitions: dict[str, tuple[Any, str]] = {}
        self.used: set[str] = set()
        self.chain: list[str] = []  # the subtrees being inserted, outermost first

    def tree(self, files: _Files, main_path: Path) -> TreeSpec:
        """Check every file's top level and subtrees, walk the roots, resolve references."""
        checker = self.checker
        name: str | None = None
        description = ""
        for path, (shown, document) in files.documents.items():
            self.file = checker.file = shown
            if "format" not in document:
                raise _NotOrdinaryError
            top = {key: _checked(_TOP_LEVEL[key], document[key])
                   for key in ("format", "name", "description") if key in document}
            file_name = top.get("name")
            file_description = top.get("description", "")
            if path == main_path:
                name, description = file_name, file_description
            if "subtrees" in document:
                self.subtrees(document["subtrees"])
        root = None
        for path, (shown, document) in files.documents.items():
            entry = document.get("root")
            if entry is None:
                continue
            if type(entry) is not tuple:
                raise _NotOrdinaryError  # not a mapping
            self.file = checker.file = shown
            if path == main_path:
                root = self.node(entry[0], 1, "0", validate._Scope(None))
            else:
                self.node(entry[0], 1, "", None)  # an included file's root: checked only
        if root is None:
            raise _NotOrdinaryError  # no root: a library file, or a mistake
        for subtree, (node, shown) in self.definitions.items():
            if subtree not in self.used:  # checked as the reference checks every definition
                self.file = shown
                self.node(node, 1, "", None)
        checker.resolve_refs()
        if checker.semantic or checker.structural:
            raise _NotOrdinaryError
        return TreeSpec(
            name=name if name is not None else main_path.stem,
            description=description,
            root=root,
            source=files.documents[main_path][0],
            plugin_paths=[],
        )

    def subtrees(self, entry: Any) -> None:
        """Note a file's subtree definitions (as ``checker_subtrees``; walked later)."""
        if type(entry) is not tuple:
            raise _NotOrdinaryError  # not a mapping
        for name, definition in entry[0].items():
            if type(definition) is not tuple or name in self.definitions:
                raise _NotOrdinaryError  # not a node, or defined twice
            self.definitions[name] = (definition[0], self.file)

    def plugin_decl(self, key: str) -> validate._Decl:
        """The declaration of a plugin met for the first time (give up on anything else)."""
        plugin = self.registry.get(key) if key != SUBTREE else None
        if plugin is None:
            raise _NotOrdinaryError
        decl = self.decls[key] = self.checker.plugin_decl(plugin)
        return decl

    def node(
        self, y: Any, depth: int, uid: str, scope: validate._Scope | None
    ) -> NodeSpec:
        """The reference walk's success path (see ``_Checker.node``), on plain values."""
        if type(y) is not dict or len(y) != 1 or depth > _MAX_DEPTH:
            raise _NotOrdinaryError
        [(key, entry)] = y.items()
        if key == SUBTREE:
            return self.subtree(entry, uid, scope, depth)
        if type(entry) is not tuple:
            raise _NotOrdinaryError  # the attributes are not a mapping
        given, line, col = entry
        decl = self.decls.get(key) or self.plugin_decl(key)
        where = _new_location(self.file, line, col)
        if not given and decl.plain_leaf:
            return NodeSpec(key, _LEAF, key, uid, where, dict(decl.defaults), [], None, {}, None)
        by_name = decl.by_name
        values: dict[str, Any] = {}
        children: list[NodeSpec] = []
        for name, value in given.items():
            attr = by_name.get(name)
            if attr is None:
                raise _NotOrdinaryError
            kind = attr.type
            if kind is _NODES:
                if type(value) is not list or not value:
                    raise _NotOrdinaryError
                values[name] = True
                for index, item in enumerate(value):
                    child_uid = f"{uid}.{index}" if scope is not None else ""
                    children.append(self.node(item, depth + 1, child_uid, scope))
            elif kind is _NODE:
                if type(value) is not tuple:
                    raise _NotOrdinaryError
                values[name] = True
                child_uid = uid + ".0" if scope is not None else ""
                children.append(self.node(value[0], depth + 1, child_uid, scope))
            elif (kind is _STRING and attr.simple and type(value) is str) or (
                kind is _BOOLEAN and type(value) is bool and attr.enum is None
            ):
                values[name] = value
            else:
                values[name] = _checked(attr, value)
        for required in decl.required_names:
            if required not in values:
                raise _NotOrdinaryError
        for rule in decl.rules:
            decides = rule.if_attr in given and _same(given[rule.if_attr], rule.equals)
            what = rule.then if decides else rule.otherwise
            present = rule.attr in given
            if (what == "required" and not present) or (what == "forbidden" and present):
                raise _NotOrdinaryError
        spec = validate.new_spec(decl, key, values, children, uid=uid, where=where)
        if scope is not None:
            self.checker.in_scope(spec, decl, scope)
        return spec

    def subtree(
        self, name: Any, uid: str, scope: validate._Scope | None, depth: int
    ) -> NodeSpec:
        """``{subtree: NAME}``: a placeholder in a definition, a fresh copy in the tree.

        The copy is the definition walked again, in a scope of its own (its ids are
        local to it), as ``_Checker.expand`` makes it from a copy of the definition.
        """
        if type(name) is not str or not name:
            raise _NotOrdinaryError
        if scope is None:
            # Only diagnostics would print where a placeholder stands, and any diagnostic
            # sends the tree to the reference path.
            return NodeSpec(SUBTREE, _LEAF, name, "", _new_location(self.file, 1, 1))
        definition = self.definitions.get(name)
        if definition is None or name in self.chain:
            raise _NotOrdinaryError  # an unknown or recursive subtree
        node, shown = definition
        outer = self.file
        self.file = shown
        self.chain.append(name)
        copy = self.node(node, depth, uid, validate._Scope(scope))
        self.chain.pop()
        self.file = outer
        self.used.add(name)
        if copy.subtree is None:  # a definition that is itself {subtree: X}: X's name stays
            copy.subtree = name
        return copy


def _same(value: Any, wanted: Any) -> bool:
    """A rule's test: a scalar of the same type and value (as ``_Checker.rule``)."""
    return type(value) is type(wanted) and value == wanted


def _checked(attr: Attr, value: Any) -> Any:
    """``_Checker.check_value`` on a plain value: the converted value, or give up."""
    kind = attr.type
    vtype = type(value)
    if kind is _STRINGS:
        if vtype is not list or any(type(item) is not str for item in value):
            raise _NotOrdinaryError
        if attr.min_items is not None and len(value) < attr.min_items:
            raise _NotOrdinaryError
        return list(value)
    if vtype is list or vtype is tuple or vtype is dict:
        raise _NotOrdinaryError
    if value is None and attr.nullable:
        return None
    if kind is _STRING:
        good = vtype is str
    elif kind is _BOOLEAN:
        good = vtype is bool
    elif kind is _INTEGER:
        good = vtype is int or (vtype is float and value.is_integer())
    elif kind is _NUMBER:
        good = vtype is int or vtype is float
    else:
        good = False
    if not good or (attr.enum is not None and value not in attr.enum):
        raise _NotOrdinaryError
    if kind is _STRING:
        if attr.min_length is not None and len(value) < attr.min_length:
            raise _NotOrdinaryError
        return value
    if kind is _BOOLEAN:
        return value
    if (
        (attr.minimum is not None and value < attr.minimum)
        or (attr.exclusive_minimum is not None and value <= attr.exclusive_minimum)
        or (attr.maximum is not None and value > attr.maximum)
        or (attr.excluded and value in attr.excluded)
    ):
        raise _NotOrdinaryError
    if kind is _INTEGER:
        return int(value)
    if not math.isfinite(value):
        raise _NotOrdinaryError
    return float(value)
