"""The quick path of :func:`~.validate.validate_file`: an ordinary, valid tree, fast.

Most loads are of a tree that is valid and plainly written: one file (no ``include``
or ``subtrees``), in the YAML subset :mod:`.quick_yaml` reads. For such a
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
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from sar_framework.engine import quick_yaml, validate, yaml_source
from sar_framework.engine.node_kinds import SUBTREE, Attr, AttrType
from sar_framework.engine.registry import Registry
from sar_framework.engine.spec import Category, NodeSpec, TreeSpec

_TOP_LEVEL_KEYS = frozenset(("format", "name", "description", "plugins", "root"))
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
) -> tuple[validate.ValidationResult, bytes] | None:
    """Validate an ordinary tree file quickly, or give up.

    Args:
        main_path: The file (absolute, normalised, as :func:`~.validate.main_file`).
        shown: Its name in diagnostics and in the spec's ``source``.
        base: Built-ins and entry points.
        plugin_paths: Extra plugin files, dirs or modules (like ``--plugin-path``).

    Returns:
        The result (with no diagnostics) and the exact bytes read; None when the
        file is not an ordinary valid tree (the caller then takes the reference path).
    """
    try:
        with main_path.open("rb") as stream:
            data = stream.read(yaml_source.MAX_FILE_BYTES + 1)
        if len(data) > yaml_source.MAX_FILE_BYTES:
            return None
        text = data.decode("utf-8-sig")
    except (OSError, UnicodeDecodeError):
        return None
    document = quick_yaml.parse(text)
    if document is None:
        return None
    try:
        entries = _checked(validate.TOP_LEVEL["plugins"], document.get("plugins", []))
    except _NotOrdinaryError:
        return None
    directory = main_path.parent
    # Plugin files are imported once per process (Registry.import_file), so giving up
    # after this costs the reference path nothing.
    registry = validate.local_registry(base, plugin_paths,
                                       [(entry, directory, None) for entry in entries])
    if registry.diagnostics:
        return None  # the reference result carries them
    try:
        spec = _Walk(registry, shown).tree(document, main_path)
    except _NotOrdinaryError:
        return None
    spec.plugin_paths = [validate.plugin_path(entry, directory) for entry in entries]
    result = validate.ValidationResult(spec, [], [], registry, None, {main_path: shown},
                                       [(entry, directory) for entry in entries])
    return result, data


class _Walk:
    """One quick walk: the reference checker's state, fed from plain values."""

    def __init__(self, registry: Registry, shown: str) -> None:
        self.checker = validate._Checker(registry)
        self.checker.file = shown
        self.registry = registry
        self.file = shown
        self.decls = dict(validate._KIND_DECLS)  # plus each plugin met, on first use

    def tree(self, document: quick_yaml.Mapping, main_path: Path) -> TreeSpec:
        """Check the top level, walk the root, resolve references."""
        if not _TOP_LEVEL_KEYS.issuperset(document):
            raise _NotOrdinaryError
        form = document.get("format")
        if type(form) is not int or form != validate.FORMAT_VERSION:
            raise _NotOrdinaryError
        name = document.get("name")
        description = document.get("description", "")
        if (name is not None and type(name) is not str) or type(description) is not str:
            raise _NotOrdinaryError
        root_entry = document.get("root")
        if type(root_entry) is not tuple:
            raise _NotOrdinaryError  # no root, or not a mapping
        root = self.node(root_entry[0], 1, "0", validate._Scope(None))
        checker = self.checker
        checker.resolve_refs()
        if checker.semantic or checker.structural:
            raise _NotOrdinaryError
        return TreeSpec(
            name=name if name is not None else main_path.stem,
            description=description,
            root=root,
            source=self.file,
            plugin_paths=[],
        )

    def plugin_decl(self, key: str) -> validate._Decl:
        """The declaration of a plugin met for the first time (give up on anything else)."""
        plugin = self.registry.get(key) if key != SUBTREE else None
        if plugin is None:
            raise _NotOrdinaryError
        decl = self.decls[key] = self.checker.plugin_decl(plugin)
        return decl

    def node(self, y: Any, depth: int, uid: str, scope: validate._Scope) -> NodeSpec:
        """The reference walk's success path (see ``_Checker.node``), on plain values."""
        if type(y) is not dict or len(y) != 1 or depth > _MAX_DEPTH:
            raise _NotOrdinaryError
        [(key, entry)] = y.items()
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
                    children.append(self.node(item, depth + 1, f"{uid}.{index}", scope))
            elif kind is _NODE:
                if type(value) is not tuple:
                    raise _NotOrdinaryError
                values[name] = True
                children.append(self.node(value[0], depth + 1, uid + ".0", scope))
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
        self.checker.in_scope(spec, decl, scope)
        return spec


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
