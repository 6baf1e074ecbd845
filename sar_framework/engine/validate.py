"""Tree file -> :class:`~.spec.TreeSpec`, or every problem found, in one pass.

The checks come in two layers, each collecting all of its diagnostics:

* structural: exactly what the generated JSON Schema (:mod:`.schema`) says,
  checked straight on the composed YAML nodes (so every message has a line
  and column) from the same declarations the schema is generated from
  (:mod:`.node_kinds`, the plugin :class:`~.plugin.Param` s). A test proves this
  layer and ``jsonschema`` on the generated schema agree on every document.
* semantic: what a schema cannot say: includes and their cycles, subtree names
  and recursion, unique ids, references to other leaves (existence, plugin type,
  cycles), ``selected`` children, finite numbers, a ``root`` in the main file.

Errors in an included file point into that file.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from yaml.nodes import MappingNode, Node, ScalarNode, SequenceNode

from sar_framework.engine import yaml_source
from sar_framework.engine.diagnostics import (
    Diagnostic,
    SourceLocation,
    did_you_mean,
    display_path,
)
from sar_framework.engine.node_kinds import (
    KINDS,
    SUBTREE,
    UNSUPPORTED_DECORATORS,
    Attr,
    AttrType,
    NodeKind,
    Rule,
    leaf_attrs,
)
from sar_framework.engine.plugin import Param, PluginSpec
from sar_framework.engine.registry import Registry, default_registry, extend
from sar_framework.engine.spec import Category, NodeSpec, TreeSpec

#: The tree format version this engine reads.
FORMAT_VERSION = 1
#: Deepest nesting of nodes accepted (keeps every recursive pass far from Python's limit).
MAX_DEPTH = 200

#: Top-level keys of a tree file, in the order the docs list them.
TOP_LEVEL_ATTRS: tuple[Attr, ...] = (
    Attr("format", AttrType.INTEGER, required=True, enum=(FORMAT_VERSION,),
         description="The tree format version; always 1."),
    Attr("name", AttrType.STRING, description="The tree's name (default: the file name)."),
    Attr("description", AttrType.STRING, description="Free text."),
    Attr("plugins", AttrType.STRINGS,
         description="Extra plugin modules, .py files or directories, relative to this file."),
    Attr("include", AttrType.STRINGS,
         description="Tree files whose subtrees become available here, relative to this file."),
    Attr("subtrees", AttrType.NODE, description="Named fragments, inserted with {subtree: NAME}."),
    Attr("root", AttrType.NODE, description="The root node (required in the file you load)."),
)  # fmt: skip
#: The top-level attributes by key.
TOP_LEVEL = {a.name: a for a in TOP_LEVEL_ATTRS}

_TYPE_WORDS = {
    AttrType.STRING: "a string",
    AttrType.INTEGER: "an integer",
    AttrType.NUMBER: "a number",
    AttrType.BOOLEAN: "a boolean (true or false)",
    AttrType.NODES: "a list of nodes",
    AttrType.STRINGS: "a list of strings",
    AttrType.NODE: "a node",
}


def _describe(node: Node, value: Any = None) -> str:
    """Say what a YAML value is, for 'got ...' in messages."""
    if type(node) is MappingNode:
        return "a mapping"
    if type(node) is SequenceNode:
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
    return f"a {type(value).__name__} '{node.value}' (quote it to make a string)"


class _Decl:
    """The attributes of one node kind, indexed for the walk."""

    __slots__ = (
        "attrs", "by_name", "defaults", "kind", "names", "plain_leaf", "plugin", "required",
        "required_names", "rules",
    )

    def __init__(
        self, attrs: Sequence[Attr], kind: NodeKind | None, plugin: PluginSpec | None
    ) -> None:
        self.attrs = tuple(attrs)
        self.by_name = {a.name: a for a in attrs}
        self.names = [a.name for a in attrs]
        self.required = [a for a in attrs if a.required]
        self.required_names = tuple(a.name for a in self.required)
        # Defaults filled into NodeSpec.attrs: params for a leaf; for a composite or
        # decorator its settings (``selected`` has no default, ``name`` is not a setting).
        skip = ("name", "id") if plugin is not None else ("name", "selected")
        self.defaults = {a.name: a.default for a in attrs if not a.required and a.name not in skip}
        self.rules: tuple[Rule, ...] = kind.rules if kind is not None else ()
        self.kind = kind
        self.plugin = plugin
        # A leaf that `Plugin: {}` fully describes (nothing required).
        self.plain_leaf = plugin is not None and not self.required


_NODE = AttrType.NODE
_NODES = AttrType.NODES
_STRING = AttrType.STRING
_BOOLEAN = AttrType.BOOLEAN
# PyYAML's YAML 1.1 booleans (SafeConstructor.bool_values), for the fast path.
_BOOLS: dict[str, bool] = dict(yaml_source.BOOL_VALUES)
BOOL_TAG = yaml_source.BOOL_TAG
_LEAF = Category.LEAF
_new_location = yaml_source.new_location
MAP_TAG = yaml_source.MAP_TAG
STR_TAG = yaml_source.STR_TAG

#: Marks an attribute that was present but invalid (so it is not also reported missing).
_INVALID = object()

_KIND_DECLS = {key: _Decl(kind.attrs, kind, None) for key, kind in KINDS.items()}
_TOP_DECL = _Decl(TOP_LEVEL_ATTRS, None, None)


@dataclass
class _Subtree:
    name: str
    node: NodeSpec | None
    location: SourceLocation
    file: Path


@dataclass
class _File:
    path: Path
    shown: str
    reader: yaml_source.Reader
    entries: dict[str, tuple[Node, Node]] = field(default_factory=dict)


class _Scope:
    """Ids visible at one level: the tree, or one copy of a subtree."""

    __slots__ = ("ids", "parent")

    def __init__(self, parent: _Scope | None) -> None:
        self.ids: dict[str, NodeSpec] = {}
        self.parent = parent

    def find(self, ident: str) -> NodeSpec | None:
        scope: _Scope | None = self
        while scope is not None:
            found = scope.ids.get(ident)
            if found is not None:
                return found
            scope = scope.parent
        return None

    def visible(self) -> list[str]:
        names: list[str] = []
        scope: _Scope | None = self
        while scope is not None:
            names.extend(scope.ids)
            scope = scope.parent
        return names


@dataclass
class ValidationResult:
    """What validating a tree file produced.

    Attributes:
        spec: The validated tree, or None when there were errors.
        diagnostics: Every problem found (errors and warnings), sorted by location.
        structural: The subset that the JSON Schema also flags (for tests).
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


def _dedupe(diagnostics: list[Diagnostic]) -> list[Diagnostic]:
    seen: set[Diagnostic] = set()
    out = []
    for d in diagnostics:
        if d not in seen:
            seen.add(d)
            out.append(d)
    out.sort(key=lambda d: (d.location.file, d.location.line, d.location.col))
    return out


class _Checker:
    """One validation run over a tree file and its includes."""

    def __init__(
        self, registry: Registry, on_read: Callable[[Path, bytes], None] | None = None
    ) -> None:
        self.registry = registry
        self.on_read = on_read
        self.structural: list[Diagnostic] = []
        self.semantic: list[Diagnostic] = []
        self.plugin_decls: dict[str, _Decl] = {}
        self.subtrees: dict[str, _Subtree] = {}
        self.value_locs: dict[tuple[SourceLocation, str], Any] = {}
        self.pending_refs: list[tuple[NodeSpec, _Scope]] = []
        self.ref_kinds: set[str] = set()  # plugins with reference params
        self.incomplete: set[int] = set()  # id() of specs that lost a child to an error
        self.reader: yaml_source.Reader = yaml_source.Reader("", self.structural)
        self.file = ""
        self.files: dict[Path, _File | None] = {}
        self.plugin_entries: list[tuple[str, Path, SourceLocation]] = []

    # -- messages -----------------------------------------------------------------------
    def error(self, node: Node, message: str) -> None:
        self.structural.append(Diagnostic(yaml_source.location(node, self.file), message))

    def semantic_error(self, where: SourceLocation, message: str) -> None:
        self.semantic.append(Diagnostic(where, message))

    # -- files --------------------------------------------------------------------------
    def open(self, path: Path, shown: str) -> _File | None:
        """Read one file's top level; the walk of its nodes comes later."""
        root, problems = yaml_source.read(path, shown, self.on_read)
        self.structural.extend(problems)
        reader = yaml_source.Reader(shown, self.structural)
        result = _File(path, shown, reader)
        if root is None:
            if not problems:
                self.structural.append(
                    Diagnostic(SourceLocation(shown, 1, 1), "empty file: a tree file needs "
                               "'format: 1' and a 'root' node")
                )
            return None
        if type(root) is not MappingNode:
            reader.error(root, f"a tree file is a mapping (format, name, root, ...), "
                               f"got {_describe(root, _scalar_or_none(reader, root))}")
            return None
        entries = reader.items(root)
        if entries is None:
            return None
        for key, key_node, value_node in entries:
            if key not in TOP_LEVEL:
                reader.error(key_node, f"unknown top-level key '{key}'"
                             + _suggest(key, _TOP_DECL.names))
                continue
            result.entries[key] = (key_node, value_node)
        if "format" not in result.entries:
            reader.error(root, "missing 'format: 1' (the tree format version)")
        return result

    def visit(self, file_path: Path, file_shown: str, stack: tuple[Path, ...]) -> None:
        """Open a file, note its plugin entries and visit its includes (depth first)."""
        opened = self.open(file_path, file_shown)
        self.files[file_path] = opened
        if opened is None:
            return
        for entry, node in self.string_list(opened, "plugins"):
            where = yaml_source.location(node, file_shown)
            self.plugin_entries.append((entry, file_path.parent, where))
        for entry, node in self.string_list(opened, "include"):
            target = Path(entry).expanduser()
            target = (file_path.parent / target) if not target.is_absolute() else target
            target = Path(_normalise(target))
            where = yaml_source.location(node, file_shown)
            if target in stack or target == file_path:
                loop = stack[stack.index(target) :] if target in stack else ()
                names = [display_path(p) for p in (*loop, file_path)]
                cycle = " -> ".join((*names, display_path(target)))
                self.semantic_error(where, f"include cycle: {cycle}")
                continue
            if target in self.files:
                continue
            if not target.is_file():
                what = "is not a file" if target.exists() else "does not exist"
                self.semantic_error(where, f"included file '{entry}' {what}")
                self.files[target] = None
                continue
            self.visit(target, display_path(target), (*stack, file_path))

    def string_list(self, file: _File, key: str) -> list[tuple[str, Node]]:
        """Check a top-level list of strings (plugins, include) and return its entries."""
        entry = file.entries.get(key)
        if entry is None:
            return []
        self.reader, self.file = file.reader, file.shown
        attr = TOP_LEVEL[key]
        ok, value = self.check_value(attr, entry[1], key)
        return value if ok else []

    def top_level(self, file: _File) -> tuple[str | None, str]:
        """Check format, name and description; return (name, description)."""
        self.reader, self.file = file.reader, file.shown
        name = None
        description = ""
        for key in ("format", "name", "description"):
            entry = file.entries.get(key)
            if entry is None:
                continue
            ok, value = self.check_value(TOP_LEVEL[key], entry[1], key)
            if not ok:
                continue
            if key == "format" and value != FORMAT_VERSION:
                continue
            if key == "name":
                name = value
            elif key == "description":
                description = value
        return name, description

    # -- values -------------------------------------------------------------------------
    def check_value(self, attr: Attr, node: Node, owner: str) -> tuple[bool, Any]:
        """Check a scalar or string-list value against ``attr``; return (ok, value)."""
        kind = attr.type
        if kind is AttrType.STRINGS:
            if type(node) is not SequenceNode:
                value = self.reader.scalar(node)[1] if type(node) is ScalarNode else None
                self.error(node, f"'{attr.name}' must be a list of strings, "
                                 f"got {_describe(node, value)}")
                return False, None
            items = self.reader.sequence(node)
            if items is None:
                return False, None
            out = []
            good = True
            for item in items:
                value = None
                if type(item) is ScalarNode:
                    ok, value = self.reader.scalar(item)
                    if not ok:
                        good = False
                        continue
                    if isinstance(value, str):
                        out.append((value, item))
                        continue
                self.error(item, f"items of '{attr.name}' must be strings, "
                                 f"got {_describe(item, value)}")
                good = False
            if attr.min_items is not None and len(items) < attr.min_items:
                self.error(node, f"'{attr.name}' must not be empty")
                good = False
            return good, out
        if type(node) is not ScalarNode:
            self.error(node, f"'{attr.name}' must be {_TYPE_WORDS[kind]}, got {_describe(node)}")
            return False, None
        ok, value = self.reader.scalar(node)
        if not ok:
            return False, None
        if value is None and attr.nullable:
            return True, None
        vtype = type(value)
        if kind is AttrType.STRING:
            good = vtype is str
        elif kind is AttrType.BOOLEAN:
            good = vtype is bool
        elif kind is AttrType.INTEGER:
            # JSON Schema: 2.0 is an integer; a bool is not a number.
            good = vtype is int or (vtype is float and value.is_integer())
        elif kind is AttrType.NUMBER:
            good = vtype is int or vtype is float
        else:  # pragma: no cover - node kinds never reach here
            good = False
        if not good:
            self.error(node, f"'{attr.name}' must be {_TYPE_WORDS[kind]}, "
                             f"got {_describe(node, value)}")
            return False, None
        if attr.enum is not None and value not in attr.enum:
            choices = ", ".join(str(c) for c in attr.enum)
            hint = did_you_mean(value, [str(c) for c in attr.enum]) if vtype is str else ""
            self.error(node, f"'{attr.name}' must be one of: {choices}; got "
                             f"{_describe(node, value)}{hint}")
            return False, None
        if kind is AttrType.STRING:
            if attr.min_length is not None and len(value) < attr.min_length:
                self.error(node, f"'{attr.name}' must not be empty")
                return False, None
            return True, value
        if kind is AttrType.INTEGER or kind is AttrType.NUMBER:
            # Same comparisons as JSON Schema (so NaN passes them, as it does there).
            problem = None
            if attr.minimum is not None and value < attr.minimum:
                problem = f">= {_num(attr.minimum)}"
            elif attr.exclusive_minimum is not None and value <= attr.exclusive_minimum:
                problem = f"> {_num(attr.exclusive_minimum)}"
            elif attr.maximum is not None and value > attr.maximum:
                problem = f"<= {_num(attr.maximum)}"
            if problem is not None:
                self.error(node, f"'{attr.name}' must be {problem}, got {_num(value)}")
                return False, None
            if attr.excluded and value in attr.excluded:
                self.error(node, f"'{attr.name}' must not be {_num(value)}")
                return False, None
            if kind is AttrType.INTEGER:
                return True, int(value)
            if not math.isfinite(value):
                self.semantic_error(yaml_source.location(node, self.file),
                                    f"'{attr.name}' must be a finite number, got {value}")
                return False, None
            return True, float(value)
        return True, value

    # -- nodes --------------------------------------------------------------------------
    def plugin_decl(self, plugin: PluginSpec) -> _Decl:
        decl = self.plugin_decls.get(plugin.name)
        if decl is None:
            decl = self.plugin_decls[plugin.name] = _Decl(leaf_attrs(plugin), None, plugin)
            if any(p.ref is not None for p in plugin.params):
                self.ref_kinds.add(plugin.name)
        return decl

    def node(
        self, y: Node, depth: int, uid: str = "", scope: _Scope | None = None
    ) -> NodeSpec | None:
        """Check one node and everything below it; return its spec or None.

        A node with problems in its own attributes still yields a (partial) spec, so
        the semantic checks below it run in the same pass; any structural error keeps
        the tree from loading. This is the hot loop of a load, written for speed.

        In the main tree (``scope`` given) the walk also assigns uids, collects ids and
        references, and inserts subtree copies; a subtree definition is walked without
        a scope, once, and each copy is expanded where it is used.
        """
        if type(y) is not MappingNode:
            self.not_a_node(y)
            return None
        pairs = y.value
        if len(pairs) == 1 and y.tag == MAP_TAG and pairs[0][0].tag == STR_TAG:
            key_node, value_node = pairs[0]
            key = key_node.value
        else:
            entries = self.reader.items(y)
            if entries is None:
                return None
            if len(entries) != 1:
                self.node_keys(y, entries)
                return None
            key, key_node, value_node = entries[0]
        mark = key_node.start_mark
        where = _new_location(self.file, mark.line + 1, mark.column + 1)
        if depth > MAX_DEPTH:
            self.semantic_error(where, f"the tree is nested deeper than {MAX_DEPTH} levels")
            return None
        if key == SUBTREE:
            placeholder = self.subtree_ref(value_node, where)
            if placeholder is None or scope is None:
                return placeholder
            return self.expand(placeholder, uid, scope, (), depth)
        decl = self.plugin_decls.get(key) or _KIND_DECLS.get(key)
        if decl is None:
            plugin = self.registry.get(key)
            if plugin is None:
                self.unknown_kind(key_node, key)
                return None
            decl = self.plugin_decl(plugin)
        if type(value_node) is not MappingNode:
            what = _describe(value_node, _scalar_or_none(self.reader, value_node))
            hint = f" (write '{key}: {{}}')" if what == "null" else ""
            self.error(value_node, f"the attributes of '{key}' must be a mapping, got {what}{hint}")
            return None
        if not value_node.value and decl.plain_leaf and value_node.tag == MAP_TAG:
            # `- Plugin: {}` with no required params: the most common node of all.
            return NodeSpec(key, _LEAF, key, uid, where, dict(decl.defaults), [], None, {}, None)
        if value_node.value:
            entries = self.reader.items(value_node)
            if entries is None:
                return None
        else:
            entries = []
        by_name = decl.by_name
        values: dict[str, Any] = {}
        children: list[NodeSpec] = []
        complete = True
        invalid = False
        for name, name_node, node in entries:
            attr = by_name.get(name)
            if attr is None:
                self.unknown_attr(name_node, name, key, decl)
                continue
            kind = attr.type
            if kind is _NODES:
                values[name] = True
                if type(node) is not SequenceNode:
                    self.error(node, f"'{name}' must be a list of nodes, got "
                                     f"{_describe(node, _scalar_or_none(self.reader, node))}")
                    continue
                items = self.reader.sequence(node)
                if items is None:
                    continue
                if not items:
                    self.error(node, f"{key} has no children (a composite needs at least one)")
                for index, item in enumerate(items):
                    child = self.node(
                        item, depth + 1, f"{uid}.{index}" if scope is not None else "", scope
                    )
                    if child is None:
                        complete = False
                    else:
                        children.append(child)
            elif kind is _NODE:
                values[name] = True
                child = self.node(node, depth + 1, uid + ".0" if scope is not None else "", scope)
                if child is None:
                    complete = False
                else:
                    children.append(child)
            elif kind is _STRING and attr.simple and node.tag == STR_TAG:
                values[name] = node.value  # the common case, without the general checks
            elif (
                kind is _BOOLEAN
                and node.tag == BOOL_TAG
                and (flag := _BOOLS.get(node.value.lower())) is not None
            ):
                values[name] = flag
            else:
                ok, value = self.check_value(attr, node, key)
                if not ok:
                    invalid = True
                    values[name] = _INVALID
                    continue
                if attr.ref is not None:
                    self.value_locs[(where, name)] = yaml_source.location(node, self.file)
                elif kind is AttrType.STRINGS:
                    self.value_locs[(where, name)] = [
                        yaml_source.location(n, self.file) for _, n in value
                    ]
                    value = [v for v, _ in value]
                values[name] = value
        for required in decl.required_names:
            if required not in values:
                self.missing(key_node, key, decl.by_name[required], values.get("name"))
        if decl.rules:
            for rule in decl.rules:
                self.rule(rule, key_node, entries, key)
        if invalid:
            values = {k: v for k, v in values.items() if v is not _INVALID}
        spec = new_spec(decl, key, values, children, uid=uid, where=where)
        if scope is not None and complete:  # (a leaf is always complete)
            self.in_scope(spec, decl, scope)
        if not complete:
            self.incomplete.add(id(spec))
        return spec

    def in_scope(self, spec: NodeSpec, decl: _Decl, scope: _Scope) -> None:
        """Note a node of the main tree: a leaf's id and references, a parallel's picks."""
        if decl.plugin is not None:
            if spec.id is not None:
                self.add_id(spec, scope)
            if spec.kind in self.ref_kinds:
                self.pending_refs.append((spec, scope))
        elif spec.kind == "parallel" and spec.attrs.get("selected") is not None:
            self.check_selected(spec)

    def rule(
        self, rule: Rule, key_node: Node, entries: list[tuple[str, Node, Node]], key: str
    ) -> None:
        present = {n: node for n, _, node in entries}
        decider = present.get(rule.if_attr)
        matches = False
        if decider is not None and type(decider) is ScalarNode:
            ok, value = self.reader.scalar(decider)
            matches = ok and type(value) is type(rule.equals) and value == rule.equals
        what = rule.then if matches else rule.otherwise
        condition = ("when" if matches else "unless") + f" {rule.if_attr} is {rule.equals}"
        if what == "required" and rule.attr not in present:
            self.error(key_node, f"{key} needs '{rule.attr}' {condition}")
        elif what == "forbidden" and rule.attr in present:
            name_node = next(k for n, k, _ in entries if n == rule.attr)
            self.error(name_node, f"'{rule.attr}' is not allowed {condition}")

    def subtree_ref(self, value_node: Node, where: SourceLocation) -> NodeSpec | None:
        value = None
        if type(value_node) is ScalarNode:
            ok, value = self.reader.scalar(value_node)
            if not ok:
                return None
            if isinstance(value, str) and value:
                return NodeSpec(SUBTREE, Category.LEAF, value, "", where)
        self.error(value_node, f"'subtree' must name a subtree, got {_describe(value_node, value)}")
        return None

    # -- node problems ------------------------------------------------------------------
    def not_a_node(self, y: Node) -> None:
        if type(y) is SequenceNode and self.reader.sequence(y) is None:
            return  # a tagged list: the tag is the problem, reported
        value = None
        if type(y) is ScalarNode:
            ok, value = self.reader.scalar(y)
            if not ok:
                return
        hint = ""
        if isinstance(value, str) and (value in KINDS or value in self.registry):
            hint = f" (write '{value}: {{}}')"
        self.error(y, "expected a node: a one-key mapping such as 'NavigateToZone: {}', "
                      f"got {_describe(y, value)}{hint}")

    def node_keys(self, y: MappingNode, entries: list[tuple[str, Node, Node]]) -> None:
        if not entries:
            self.error(y, "empty node: expected one key naming the node kind")
            return
        keys = [k for k, _, _ in entries]
        first = keys[0]
        decl = _KIND_DECLS.get(first)
        plugin = self.registry.get(first)
        if decl is None and plugin is not None:
            decl = self.plugin_decl(plugin)
        hint = ""
        if decl is not None and all(k in decl.by_name for k in keys[1:]):
            hint = f" (indent the attributes under '{first}')"
        shown = ", ".join(f"'{k}'" for k in keys)
        self.error(entries[1][1], f"a node has exactly one key, its kind; got {shown}{hint}")

    def unknown_kind(self, key_node: Node, key: str) -> None:
        if key in UNSUPPORTED_DECORATORS:
            self.error(key_node, f"decorator '{key}' is not supported: "
                                 f"{UNSUPPORTED_DECORATORS[key]}")
            return
        candidates = [*KINDS, SUBTREE, *self.registry.names()]
        self.error(key_node, f"unknown plugin '{key}'{did_you_mean(key, candidates)}")

    def unknown_attr(self, name_node: Node, name: str, key: str, decl: _Decl) -> None:
        if decl.plugin is not None:
            what = f"unknown param '{name}' for plugin '{key}'"
        else:
            what = f"unknown attribute '{name}' for {key}"
            if name == "children" and decl.kind and decl.kind.category is Category.DECORATOR:
                self.error(name_node, f"{what} (a decorator has exactly one 'child')")
                return
            if name == "child" and decl.kind and decl.kind.category is Category.COMPOSITE:
                self.error(name_node, f"{what} (a composite has a list of 'children')")
                return
        self.error(name_node, what + _suggest(name, decl.names))

    def missing(self, key_node: Node, key: str, attr: Attr, name: Any) -> None:
        label = f"{key} '{name}'" if isinstance(name, str) else key
        if attr.name == "memory":
            message = (f"{label} needs 'memory: true' (resume at the running child) or "
                       "'memory: false' (start again from the first child every tick)")
        elif attr.name == "child":
            message = f"{label} needs a 'child' (a decorator has exactly one)"
        elif attr.name == "children":
            message = f"{label} needs 'children' (a composite has at least one)"
        elif attr.type is AttrType.NODE:
            message = f"{label} needs '{attr.name}'"
        else:
            noun = "param" if key in self.registry else "attribute"
            message = f"{label} is missing required {noun} '{attr.name}'"
        self.error(key_node, message)

    # -- expansion and references ------------------------------------------------------
    def expand(
        self, node: NodeSpec, uid: str, scope: _Scope, chain: tuple[str, ...], depth: int
    ) -> NodeSpec | None:
        """Insert subtree copies, assign uids and collect ids, below ``node``."""
        if depth > MAX_DEPTH:
            self.semantic_error(node.location,
                                f"the tree is nested deeper than {MAX_DEPTH} levels")
            return None
        if node.kind == SUBTREE:
            name = node.name
            if name in chain:
                cycle = " -> ".join((*chain[chain.index(name):], name))
                self.semantic_error(node.location, f"recursive subtree: {cycle}")
                return None
            found = self.subtrees.get(name)
            if found is None:
                self.semantic_error(node.location, f"unknown subtree '{name}'"
                                    + did_you_mean(name, self.subtrees))
                return None
            if found.node is None:
                return None  # its own problems are already reported
            copy = _copy(found.node)
            copy.subtree = name
            return self.expand(copy, uid, _Scope(scope), (*chain, name), depth)
        node.uid = uid
        if node.id is not None:
            self.add_id(node, scope)
        if node.category is _LEAF:
            if node.kind in self.ref_kinds:
                self.pending_refs.append((node, scope))
            return node
        children = []
        for index, child in enumerate(node.children):
            expanded = self.expand(child, f"{uid}.{index}", scope, chain, depth + 1)
            if expanded is not None:
                children.append(expanded)
        if len(children) != len(node.children):
            self.incomplete.add(id(node))
        node.children = children
        if (
            node.kind == "parallel"
            and node.attrs.get("selected") is not None
            and id(node) not in self.incomplete
        ):
            self.check_selected(node)
        return node

    def add_id(self, node: NodeSpec, scope: _Scope) -> None:
        """Record a leaf's id in its scope; report a duplicate."""
        first = scope.ids.get(node.id)  # type: ignore[arg-type]
        if first is not None:
            self.semantic_error(node.location,
                                f"duplicate id '{node.id}' (first used at {first.location})")
        else:
            scope.ids[node.id] = node  # type: ignore[index]

    def check_selected(self, node: NodeSpec) -> None:
        names = [c.name for c in node.children]
        locs = self.value_locs.get((node.location, "selected"), [])
        for index, wanted in enumerate(node.attrs["selected"]):
            where = locs[index] if index < len(locs) else node.location
            count = names.count(wanted)
            if count == 0:
                self.semantic_error(where, f"'selected' names '{wanted}', which is not a child "
                                           f"of this parallel{did_you_mean(wanted, names)}")
            elif count > 1:
                self.semantic_error(where, f"'selected' names '{wanted}', but {count} children "
                                           "have that name")

    def resolve_refs(self) -> None:
        """Point every reference param at its leaf; report dangling, mistyped, cyclic ones."""
        edges: dict[int, list[NodeSpec]] = {}
        ref_params: dict[str, list[Param]] = {}  # per plugin, worked out once
        for leaf, scope in self.pending_refs:
            params = ref_params.get(leaf.kind)
            if params is None:
                plugin = self.registry.get(leaf.kind)
                params = [p for p in plugin.params if p.ref is not None] if plugin else []
                ref_params[leaf.kind] = params
            for param in params:
                ident = leaf.attrs.get(param.name)
                if ident is None:
                    continue
                where = self.value_locs.get((leaf.location, param.name), leaf.location)
                target = scope.find(ident)
                if target is None:
                    self.semantic_error(where, f"'{param.name}' names no leaf: there is no id "
                                               f"'{ident}'{did_you_mean(ident, scope.visible())}")
                elif target.kind != param.ref:
                    self.semantic_error(where, f"'{param.name}' must name a {param.ref} leaf, "
                                               f"but '{ident}' is a {target.kind}")
                else:
                    leaf.refs[param.name] = target
                    edges.setdefault(id(leaf), []).append(target)
        self.reference_cycles(edges)

    def reference_cycles(self, edges: dict[int, list[NodeSpec]]) -> None:
        state: dict[int, int] = {}  # 1: on the path, 2: done
        for leaf, _ in self.pending_refs:
            if id(leaf) in state or id(leaf) not in edges:
                continue
            path: list[NodeSpec] = [leaf]
            stack = [iter(edges[id(leaf)])]
            state[id(leaf)] = 1
            while stack:
                target = next(stack[-1], None)
                if target is None:
                    state[id(path.pop())] = 2
                    stack.pop()
                    continue
                mark = state.get(id(target))
                if mark is None and id(target) not in edges:
                    state[id(target)] = 2  # references nothing: no cycle through it
                elif mark == 1:
                    start = next(i for i, n in enumerate(path) if n is target)
                    cycle = " -> ".join(f"'{n.id}'" for n in (*path[start:], target))
                    self.semantic_error(path[-1].location, f"reference cycle: {cycle}")
                elif mark is None:
                    state[id(target)] = 1
                    path.append(target)
                    stack.append(iter(edges.get(id(target), ())))


def new_spec(
    decl: _Decl,
    key: str,
    values: dict[str, Any],
    children: list[NodeSpec],
    *,
    uid: str,
    where: SourceLocation,
) -> NodeSpec:
    """Make the spec of a checked node.

    Args:
        decl: The node kind's or plugin's declaration.
        key: The node's key (kind or plugin name).
        values: The attributes written, checked and converted (consumed: ``name``, a
            leaf's ``id`` and the child attributes are taken out).
        children: The child specs.
        uid: The node's uid.
        where: Where its key stands.

    Returns:
        The spec, defaults filled in.
    """
    name = values.pop("name", None)
    if decl.plugin is not None:
        ident = values.pop("id", None)
        attrs = {**decl.defaults, **values} if decl.defaults else values
        return NodeSpec(key, _LEAF, key if name is None else name, uid, where, attrs,
                        children, ident, {}, None)
    kind = decl.kind
    assert kind is not None
    values.pop("children", None)
    values.pop("child", None)
    attrs = {**decl.defaults, **values} if decl.defaults else values
    return NodeSpec(key, kind.category, kind.class_name if name is None else name, uid,
                    where, attrs, children, None, {}, None)


def _copy(node: NodeSpec) -> NodeSpec:
    return NodeSpec(node.kind, node.category, node.name, "", node.location, dict(node.attrs),
                    [_copy(c) for c in node.children], node.id, {}, node.subtree)


def _num(value: float) -> str:
    return str(int(value)) if isinstance(value, float) and value.is_integer() else str(value)


def _suggest(word: str, names: Sequence[str]) -> str:
    hint = did_you_mean(word, names)
    return hint or f" (expected one of: {', '.join(names)})"


def _scalar_or_none(reader: yaml_source.Reader, node: Node) -> Any:
    if type(node) is not ScalarNode:
        return None
    before = len(reader.diagnostics)
    ok, value = reader.scalar(node)
    del reader.diagnostics[before:]  # the caller reports its own problem
    return value if ok else None


def main_file(path: str | Path) -> Path:
    """Return the absolute, normalised path under which a tree file is validated.

    Args:
        path: The tree file, as the user named it.

    Returns:
        The path (symbolic links are kept, ``..`` is folded).
    """
    return Path(_normalise(Path(path).absolute()))


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
    on_read: Callable[[Path, bytes], None] | None = None,
    quick: bool = True,
) -> ValidationResult:
    """Validate a tree file and the files it includes.

    Args:
        path: The tree file, as the user named it (diagnostics print it that way).
        registry: The plugins to check against; default: built-ins and entry points.
        plugin_paths: Extra plugin files, dirs or modules (like ``--plugin-path``).
        on_read: Called with each tree file's path and the exact bytes read.
        quick: Try :mod:`.quick_validate` first (an ordinary valid tree, about three
            times faster, same result); False always takes the reference path.

    Returns:
        The result; ``spec`` is None when there were errors.
    """
    base = registry if registry is not None else default_registry()
    shown = str(path)
    main_path = main_file(path)
    if quick:
        from sar_framework.engine.quick_validate import quick_validate  # imports this module

        done = quick_validate(main_path, shown, base, plugin_paths)
        if done is not None:
            result, reads = done
            if on_read is not None:
                for file_path, data in reads:
                    on_read(file_path, data)
            return result
    checker = _Checker(base, on_read)

    # 1. Read the main file and, transitively, its includes (the top level only).
    checker.visit(main_path, shown, ())
    files = checker.files
    plugin_entries = checker.plugin_entries

    # 2. The registry: built-ins and entry points, plus the local plugins named.
    reg = local_registry(base, plugin_paths, plugin_entries)
    checker.registry = reg

    # 3. Walk every file's subtrees (definitions, checked once), then the roots: the
    #    main root's walk also inserts subtree copies, assigns uids and collects ids.
    main = files.get(main_path)
    tree_name: str | None = None
    description = ""
    for file_path, opened in files.items():
        if opened is None:
            continue
        name, text = checker.top_level(opened)
        if file_path == main_path:
            tree_name, description = name, text
        entry = opened.entries.get("subtrees")
        if entry is not None:
            checker.reader, checker.file = opened.reader, opened.shown
            checker_subtrees(checker, opened, entry[1])
    root: NodeSpec | None = None
    for file_path, opened in files.items():
        entry = opened.entries.get("root") if opened is not None else None
        if entry is None:
            continue
        checker.reader, checker.file = opened.reader, opened.shown  # type: ignore[union-attr]
        if file_path == main_path:
            root = checker.node(entry[1], 1, "0", _Scope(None))
        else:
            checker.node(entry[1], 1)  # an included file's root: checked, not used
    library = main is not None and "root" not in main.entries and "subtrees" in main.entries
    if main is not None and "root" not in main.entries and not library:
        checker.semantic_error(SourceLocation(shown, 1, 1), "missing 'root': the node the tree "
                                                            "starts from")

    # 4. References (every leaf that has them, in every scope).
    if root is not None:
        checker.resolve_refs()

    diagnostics = _dedupe([*reg.diagnostics, *checker.structural, *checker.semantic])
    spec = None
    if root is not None and not any(d.severity == "error" for d in diagnostics):
        spec = TreeSpec(
            name=tree_name if tree_name is not None else main_path.stem,
            description=description,
            root=root,
            source=shown,
            plugin_paths=[plugin_path(e, d) for e, d, _ in plugin_entries],
        )
    return ValidationResult(
        spec, diagnostics, _dedupe(checker.structural), reg,
        len(checker.subtrees) if library else None,
        {p: f.shown for p, f in files.items() if f is not None},
        [(entry, directory) for entry, directory, _ in plugin_entries],
    )


def checker_subtrees(checker: _Checker, opened: _File, node: Node) -> None:
    """Check a file's ``subtrees`` mapping and register each definition."""
    if type(node) is not MappingNode:
        checker.error(node, "'subtrees' must be a mapping of names to nodes, got "
                            f"{_describe(node, _scalar_or_none(checker.reader, node))}")
        return
    entries = checker.reader.items(node)
    if entries is None:
        return
    for name, name_node, value in entries:
        where = yaml_source.location(name_node, opened.shown)
        if not name:
            checker.error(name_node, "a subtree name must not be empty")
            continue
        spec = checker.node(value, 1)
        first = checker.subtrees.get(name)
        if first is not None:
            checker.semantic_error(where, f"subtree '{name}' is defined twice "
                                          f"(first at {first.location})")
            continue
        checker.subtrees[name] = _Subtree(name, spec, where, opened.path)


def _normalise(path: Path) -> str:
    return os.path.normpath(str(path))


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
