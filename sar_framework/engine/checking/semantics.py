"""Semantics: what a schema cannot say, checked while the tree's specs are made.

Subtree names and recursion (in used and unused definitions, :mod:`.subtree_defs`), every
node's ports and scripts resolved in its scope, unique ids per scope, references to other
leaves (existence, plugin type, cycles), ``selected`` children of a parallel, finite
numbers and the nesting depth. The walk is tolerant: a value the schema check rejects is
skipped here, so both layers report in the same pass.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from sar_framework.engine.checking.bindings import PORT_LOC, Bindings, located
from sar_framework.engine.checking.declarations import Declaration, declaration_of
from sar_framework.engine.checking.entries import DataScope, Entries
from sar_framework.engine.checking.references import resolve_references
from sar_framework.engine.checking.script_bindings import ScriptBindings
from sar_framework.engine.checking.subtree_defs import Subtree, copy_spec, cycle_text, report_cycles
from sar_framework.engine.diagnostics import SourceLocation, did_you_mean
from sar_framework.engine.nodes.control_kinds import threshold_problem
from sar_framework.engine.nodes.node_kinds import KINDS, MAX_DEPTH, SUBTREE, Attr, AttrType
from sar_framework.engine.ports import NO_DEFAULT
from sar_framework.engine.reading.document import DocPath, Document
from sar_framework.engine.reading.tree_files import TreeFiles
from sar_framework.engine.registry import Registry
from sar_framework.engine.spec import Category, NodeSpec

#: The message of the depth guard.
TOO_DEEP = f"the tree is nested deeper than {MAX_DEPTH} levels"


def _below(attr: Attr, value: Any) -> bool:
    """Whether a port's literal (given as text) is under the attribute's minimum."""
    return (attr.minimum is not None and isinstance(value, (int, float))
            and not isinstance(value, bool) and value < attr.minimum)


class Scope:
    """Ids visible at one level: the tree, or one copy of a subtree (and its entries)."""

    def __init__(self, parent: Scope | None, data: DataScope | None = None) -> None:
        self.ids: dict[str, NodeSpec] = {}
        self.parent = parent
        self.data: DataScope = data or (parent.data if parent else DataScope("", "the tree"))

    def find(self, ident: str) -> NodeSpec | None:
        """Return the leaf with ``ident`` here or in an enclosing scope."""
        scope: Scope | None = self
        while scope is not None:
            if ident in scope.ids:
                return scope.ids[ident]
            scope = scope.parent
        return None

    def visible(self) -> list[str]:
        """Return every id visible here."""
        names: list[str] = []
        scope: Scope | None = self
        while scope is not None:
            names.extend(scope.ids)
            scope = scope.parent
        return names


class Semantics:
    """One validation run over a tree file and its includes, once they are read.

    Args:
        registry: The plugins the tree is checked against (with its own ``plugins:``).
        files: The files read; the walk's problems join their ``semantic`` list.

    Attributes:
        subtrees: The subtree definitions of every file, by name.
    """

    def __init__(self, registry: Registry, files: TreeFiles) -> None:
        self.files, self.structural, self.semantic = files.files, files.structural, files.semantic
        self.error, self.registry = files.error, registry
        self.subtrees: dict[str, Subtree] = {}
        self.used_subtrees: set[str] = set()
        self.declarations: dict[str, Declaration | None] = {}
        self.value_locs: dict[tuple[SourceLocation, str], Any] = {}
        self.pending_refs: list[tuple[NodeSpec, Scope]] = []
        self.incomplete: set[int] = set()  # id() of specs that lost a child to an error
        self.entries = Entries(self.error)
        self.bindings = Bindings(self.entries, self.error)
        self.scripts = ScriptBindings(self.entries, self.error)

    # -- the walk -----------------------------------------------------------------------
    def walk(self, main: Path) -> NodeSpec | None:
        """Make every file's subtrees, then the roots; return the main tree's root spec."""
        for doc in self.files.values():
            definitions = doc.value.get("subtrees") if doc is not None else None
            if not isinstance(definitions, dict):
                continue
            for name, value in definitions.items():
                top, at, ports, local = self.bindings.definition(doc, name, value)  # type: ignore
                spec = self.node(doc, top, at, 1)  # type: ignore[arg-type]
                where = doc.key_where(("subtrees", name))  # type: ignore[union-attr]
                first = self.subtrees.get(name)
                if first is not None:
                    self.error(where, f"subtree '{name}' is defined twice "
                                      f"(first at {first.location})")
                elif name:
                    self.subtrees[name] = Subtree(name, spec, where, ports, local)
        root = None
        for path, doc in self.files.items():
            if doc is None:
                continue
            if path != main and "blackboard" in doc.value:
                self.error(doc.key_where(("blackboard",)), "'blackboard' is only read from the "
                           "main tree file; declare an included subtree's ports instead")
            if "root" not in doc.value:
                continue
            if path == main:
                data = self.bindings.main_scope(doc)
                root = self.node(doc, doc.value["root"], ("root",), 1, "0",
                                 scope=Scope(None, data))
            else:
                self.node(doc, doc.value["root"], ("root",), 1)  # checked, not used
        done = set(self.used_subtrees)
        for name, definition in self.subtrees.items():
            if name not in done:
                report_cycles(definition.node, (name,), done, self.subtrees, self.error)
                done.add(name)
        if root is not None:
            self.resolve_refs()
            self.entries.check()
            self.bindings.check_copies(self.value_locs)
            self.scripts.check()
        return root

    def declaration(self, key: str) -> Declaration | None:
        """Return the declaration of a node kind or plugin (None when unknown)."""
        if key not in self.declarations:
            self.declarations[key] = declaration_of(key, self.registry)
        return self.declarations[key]

    def node(
        self, doc: Document, value: Any, path: DocPath, depth: int, uid: str = "",
        *, scope: Scope | None = None,
    ) -> NodeSpec | None:
        """Make the spec of one node and everything below it (None when it is not one).

        In the main tree (``scope`` given) the walk also assigns uids, collects ids and
        references, and inserts subtree copies; a subtree definition is walked without
        a scope, once, and each copy is expanded where it is used.
        """
        if not isinstance(value, dict) or len(value) != 1:
            return None
        ((key, attrs),) = value.items()
        path = (*path, key)
        where = doc.key_where(path)
        if depth > MAX_DEPTH:
            self.error(where, TOO_DEEP)
            return None
        if key == SUBTREE:
            placeholder = self.bindings.subtree_use(doc, attrs, path, where, self.value_locs)
            if placeholder is None:
                return None
            for name in [k for k in placeholder.attrs if k.startswith("_")]:
                script = self.scripts.compile(doc, (*path, name), placeholder.attrs[name])
                if script is not None:  # BT.CPP's SubTree node's conditions
                    placeholder.scripts[name] = script
            return placeholder if scope is None else self.expand(placeholder, uid, scope, (),
                                                                 depth)
        decl = self.declaration(key)
        if decl is None or not isinstance(attrs, dict):
            return None
        values: dict[str, Any] = {}
        ports: dict[str, Any] = {}
        scripts: dict[str, Any] = {}
        children: list[NodeSpec] = []
        complete = True
        for attr in decl.attrs:
            if attr.name not in attrs:
                continue
            given = attrs[attr.name]
            at = (*path, attr.name)
            if attr.port is not None:
                self.value_locs[(where, PORT_LOC + attr.name)] = value_at = doc.where(at)
                kept = self.bindings.port_value(attr.port, given, value_at, located(doc, at))
                if isinstance(given, str) and _below(attr, kept):  # the schema bounds a number
                    self.bindings.report(value_at, f"port '{attr.name}': {kept} is less than "
                                         f"the minimum of {attr.minimum}")
                    kept = NO_DEFAULT
                if kept is not NO_DEFAULT:
                    ports[attr.name] = kept
                # BT.CPP's node (or a plugin's): the text as written, for labels and export
                if key in KINDS or self.registry.kind(key):
                    values[attr.name] = given
                continue
            if attr.type is AttrType.SCRIPT:
                script = self.scripts.compile(doc, at, given)
                if script is not None:
                    scripts[attr.name] = script
                if not attr.name.startswith("_"):  # a script node's own code: shown by labels
                    values[attr.name] = given
                continue
            if (attr.type is AttrType.STRING and decl.category is Category.LEAF
                    and attr.name not in ("name", "id")
                    and self.bindings.param_value(attr.name, given, doc.where(at))):
                continue
            if attr.type in (AttrType.NODES, AttrType.NODE):
                items = [given] if attr.type is AttrType.NODE else given
                if not isinstance(items, list):
                    continue
                for index, item in enumerate(items):
                    child_uid = f"{uid}.{index}" if scope is not None else ""
                    item_path = at if attr.type is AttrType.NODE else (*at, index)
                    child = self.node(doc, item, item_path, depth + 1, child_uid, scope=scope)
                    if child is None:
                        complete = False
                    else:
                        children.append(child)
                continue
            values[attr.name] = self.number(attr, given, doc.where(at))
            if attr.ref is not None:
                self.value_locs[(where, attr.name)] = doc.where(at)
            elif attr.type is AttrType.STRINGS and isinstance(given, list):
                self.value_locs[(where, attr.name)] = [doc.where((*at, i))
                                                       for i in range(len(given))]
        name = values.pop("name", None)
        ident = values.pop("id", None) if decl.category is Category.LEAF else None
        spec = NodeSpec(key, decl.category, name if isinstance(name, str) else decl.default_name,
                        uid, where, {**decl.defaults, **values}, children,
                        ident if isinstance(ident, str) else None, {}, None, frozenset(values),
                        ports, symbol=decl.symbol)
        spec.scripts = scripts
        if not complete:
            self.incomplete.add(id(spec))
        elif scope is not None:
            self.in_scope(spec, decl, scope)
        return spec

    def number(self, attr: Attr, value: Any, where: SourceLocation) -> Any:
        """Convert a checked number to its Python type; report one that is not finite."""
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            return value
        if attr.type is AttrType.INTEGER and float(value).is_integer():
            return int(value)
        if attr.type is AttrType.NUMBER:
            if not math.isfinite(value):
                self.error(where, f"'{attr.name}' must be a finite number, got {value}")
            return float(value)
        return value

    def in_scope(self, spec: NodeSpec, decl: Declaration, scope: Scope) -> None:
        """Note a node of the main tree: its scripts and ports, resolved in its scope.

        Also a leaf's id and references, and what a composite's attributes say of its
        children.
        """
        if spec.scripts:
            self.scripts.bind(spec, scope.data)
        if decl.ports:
            self.bindings.bind_ports(spec, decl.ports, scope.data, self.value_locs)
        if decl.category is Category.LEAF:
            if spec.id is not None:
                self.add_id(spec, scope)
            if decl.ref_params:
                self.pending_refs.append((spec, scope))
        elif id(spec) not in self.incomplete:
            self.check_children(spec)

    def expand(
        self, node: NodeSpec, uid: str, scope: Scope, chain: tuple[str, ...], depth: int
    ) -> NodeSpec | None:
        """Insert subtree copies, assign uids and collect ids, below ``node``."""
        if depth > MAX_DEPTH:
            self.error(node.location,
                                f"the tree is nested deeper than {MAX_DEPTH} levels")
            return None
        if node.kind == SUBTREE:
            name = node.name
            if name in chain:
                self.error(node.location, cycle_text(chain, name))
                return None
            found = self.subtrees.get(name)
            if found is None:
                self.error(node.location, f"unknown subtree '{name}'"
                                    + did_you_mean(name, self.subtrees))
                return None
            self.used_subtrees.add(name)
            if found.node is None:
                return None  # its own problems are already reported
            copy = copy_spec(found.node)
            copy.subtree, copy.insertion = name, dict(node.attrs)
            data = self.bindings.insertion(node, (found.ports, found.local), uid, scope.data,
                                           self.value_locs)
            top = self.expand(copy, uid, Scope(scope, data), (*chain, name), depth)
            if node.scripts and top is not None:  # BT.CPP's SubTree node's conditions
                self.scripts.bind(node, scope.data)  # in the parent's scope
                last = top
                while last.use is not None:  # a subtree whose root is an insertion too
                    last = last.use
                last.use = node
            return top
        node.uid = uid
        decl = self.declaration(node.kind)
        if node.category is not Category.LEAF:
            children = []
            for index, child in enumerate(node.children):
                expanded = self.expand(child, f"{uid}.{index}", scope, chain, depth + 1)
                if expanded is not None:
                    children.append(expanded)
            if len(children) != len(node.children):
                self.incomplete.add(id(node))
            node.children = children
        if decl is not None:
            self.in_scope(node, decl, scope)
        return node

    def add_id(self, node: NodeSpec, scope: Scope) -> None:
        """Record a leaf's id in its scope; report a duplicate."""
        first = scope.ids.get(node.id)  # type: ignore[arg-type]
        if first is not None:
            self.error(node.location,
                                f"duplicate id '{node.id}' (first used at {first.location})")
        else:
            scope.ids[node.id] = node  # type: ignore[index]

    def check_children(self, node: NodeSpec) -> None:
        """Check what a composite's attributes say about its children."""
        if node.kind == "parallel" and node.attrs.get("selected") is not None:
            self.check_selected(node)
        problem = threshold_problem(node.kind, node.attrs, len(node.children))
        if problem is not None:
            self.error(node.location, problem)

    def check_selected(self, node: NodeSpec) -> None:
        """Report ``selected`` names that are not exactly one child of the parallel."""
        if not isinstance(node.attrs["selected"], list):
            return
        names = [c.name for c in node.children]
        locs = self.value_locs.get((node.location, "selected"), [])
        for index, wanted in enumerate(node.attrs["selected"]):
            if not isinstance(wanted, str):
                continue
            where = locs[index] if index < len(locs) else node.location
            count = names.count(wanted)
            if count == 0:
                self.error(where, f"'selected' names '{wanted}', which is not a child "
                                           f"of this parallel{did_you_mean(wanted, names)}")
            elif count > 1:
                self.error(where, f"'selected' names '{wanted}', but {count} children "
                                           "have that name")

    def resolve_refs(self) -> None:
        """Point every reference param at its leaf; report dangling, mistyped, cyclic ones."""
        resolve_references(self.pending_refs, self.declaration, self.value_locs, self.error)

