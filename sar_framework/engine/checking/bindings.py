"""Ports and entries in a tree file: what the semantic walk reads and resolves.

Reads a ``blackboard:`` section and a subtree definition's ``ports:``, checks a leaf's
port bindings as written (an entry's name, a literal's conversion, an output bound to
a literal, a ``{key}`` on a param), and resolves them per scope (:mod:`.entries`): a
leaf's ports in its scope, and the scope of each subtree insertion from its remapping.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from typing import Any

from sar_framework.engine.checking.entries import DataScope, Entries, Report
from sar_framework.engine.checking.schema import fits_port
from sar_framework.engine.diagnostics import SourceLocation, did_you_mean
from sar_framework.engine.message_literals import LiteralError
from sar_framework.engine.messages import LiteralPath, dotted
from sar_framework.engine.nodes.control_kinds import COPIES
from sar_framework.engine.nodes.node_kinds import SUBTREE
from sar_framework.engine.ports import (
    BASIC_TYPES,
    ENTRY_NAME,
    NO_DEFAULT,
    Direction,
    Naming,
    Port,
    PortBinding,
    compatible,
    convert,
    entry_ref,
    is_message,
    valid_type,
)
from sar_framework.engine.reading.document import DocPath, Document
from sar_framework.engine.spec import Category, Declared, NodeSpec

#: What a key prefix may not hold ('.' reads as an attribute in py_trees, '/' as a level).
_UNSAFE = re.compile(r"[^A-Za-z0-9_-]")
#: Where a part of a literal stands: its path in the literal, and whether its key is meant.
Locate = Callable[[LiteralPath, bool], SourceLocation]
#: ``value_locs`` key of a leaf port's value, and of a subtree use's port value.
PORT_LOC = "port."
USE_LOC = "ports."


def _get(doc: Document, path: DocPath) -> Any:
    value: Any = doc.value
    for part in path:
        if not isinstance(value, dict):
            return None
        value = value.get(part)
    return value


def _declarations(doc: Document, path: DocPath) -> list[tuple[str, dict[str, Any]]] | None:
    """The well-formed declarations of the section at ``path`` (None: there is none).

    A malformed one (not a mapping, or a bad name) is left to the schema check to report.
    """
    section = _get(doc, path)
    if not isinstance(section, dict):
        return None
    return [(name, decl) for name, decl in section.items()
            if isinstance(decl, dict) and ENTRY_NAME.match(name)]


def located(doc: Document, at: DocPath) -> Locate:
    """Where a part of the literal at ``at`` in ``doc`` stands (its key, or its value)."""
    def locate(path: LiteralPath, at_key: bool) -> SourceLocation:
        return (doc.key_where if at_key else doc.where)((*at, *path))
    return locate


class Bindings:
    """Port and entry handling for one validation run.

    Args:
        entries: Collects the tree's entries and uses.
        report: Where problems go.
    """

    def __init__(self, entries: Entries, report: Report) -> None:
        self.entries = entries
        self.report = report
        self.copies: list[NodeSpec] = []  # nodes of COPIES kinds, checked after the walk

    # -- declarations -------------------------------------------------------------------
    def main_scope(self, doc: Document) -> DataScope:
        """Return the main tree's scope, with its ``blackboard:`` entries declared."""
        scope = DataScope("", "the main tree", self.blackboard(doc, ("blackboard",)))
        self.entries.scopes[""] = dict(scope.declared or {})
        for name, decl in (scope.declared or {}).items():
            self.entries.declare(f"/{name}", decl)
        return scope

    def definition(
        self, doc: Document, name: str, value: Any
    ) -> tuple[Any, DocPath, dict[str, Port] | None, dict[str, Declared] | None]:
        """Split a subtree definition: its root node, the root's path, its ports and entries.

        ``NAME: NODE`` declares nothing; ``NAME: {ports, blackboard, root}`` does.
        """
        at: DocPath = ("subtrees", name)
        if not isinstance(value, dict) or "root" not in value:
            return value, at, None, None
        ports = self.subtree_ports(doc, (*at, "ports"))
        local = self.blackboard(doc, (*at, "blackboard"), caller_sets=False)
        self.entries.scopes.setdefault(name, dict(local or {}))
        return value["root"], (*at, "root"), ports, local

    def type_of(self, doc: Document, path: DocPath, given: Any) -> str:
        """Return a declared type name; report an unknown one (``any`` then)."""
        if given is None or valid_type(given):
            return given or "any"
        if isinstance(given, str):
            hint = did_you_mean(given, BASIC_TYPES) or (
                f" (expected one of: {', '.join(BASIC_TYPES)}, or pkg/msg/Type)")
            self.report(doc.where(path), f"unknown type '{given}'{hint}")
        return "any"

    def blackboard(
        self, doc: Document, path: DocPath, *, caller_sets: bool = True
    ) -> dict[str, Declared] | None:
        """Read a ``blackboard:`` section (None when there is none)."""
        declarations = _declarations(doc, path)
        if declarations is None:
            return None
        out: dict[str, Declared] = {}
        for name, decl in declarations:
            type_ = self.type_of(doc, (*path, name, "type"), decl.get("type"))
            initial = NO_DEFAULT
            if "initial" in decl:
                at = (*path, name, "initial")
                initial = self.literal(type_, decl["initial"], doc.where(at),
                                       f"initial value of '{name}'", located(doc, at))
            text = decl.get("description")
            out[name] = Declared(name, type_, initial, text if isinstance(text, str) else "",
                                 doc.key_where((*path, name)), caller_sets)
        return out

    def subtree_ports(self, doc: Document, path: DocPath) -> dict[str, Port] | None:
        """Read a subtree definition's ``ports:`` (None when it declares none)."""
        declarations = _declarations(doc, path)
        if declarations is None:
            return None
        out: dict[str, Port] = {}
        for name, decl in declarations:
            type_ = self.type_of(doc, (*path, name, "type"), decl.get("type"))
            direction = decl.get("direction", "input")
            if direction not in {d.value for d in Direction}:
                continue
            default = decl.get("default", NO_DEFAULT)
            if default is not NO_DEFAULT and entry_ref(default) is None:
                default = self.literal(type_, default, doc.where((*path, name, "default")),
                                       f"default of port '{name}'")
            text = decl.get("description")
            try:
                out[name] = Port(name, type_, default, text if isinstance(text, str) else "",
                                 Direction(direction))
            except TypeError as exc:
                self.report(doc.where((*path, name)), str(exc))
        return out

    def literal(
        self, type_: str, value: Any, where: SourceLocation, what: str, locate: Locate | None = None
    ) -> Any:
        """Return ``value`` converted to ``type_``; report it (NO_DEFAULT) when it does not.

        A message literal's problems are each reported where ``locate`` puts them (at the
        wrong field), else at ``where``.
        """
        try:
            return convert(type_, value)
        except LiteralError as exc:
            for path, text, at_key in exc.problems:
                at = locate(path, at_key) if locate is not None and path else where
                self.report(at, f"{what}: {dotted(path)}: {text}" if path else f"{what}: {text}")
            return NO_DEFAULT
        except ValueError as exc:
            self.report(where, f"{what}: {exc}")
            return NO_DEFAULT

    # -- bindings as written ------------------------------------------------------------
    def subtree_use(
        self, doc: Document, attrs: Any, path: DocPath, where: SourceLocation,
        locs: dict[tuple[SourceLocation, str], Any],
    ) -> NodeSpec | None:
        """Return the placeholder of ``subtree: NAME`` or ``subtree: {tree: NAME, ...}``."""
        name = attrs.get("tree") if isinstance(attrs, dict) else attrs
        if not isinstance(name, str) or not name:
            return None
        placeholder = NodeSpec(SUBTREE, Category.LEAF, name, "", where)
        if isinstance(attrs, dict):
            placeholder.attrs = {"ports": attrs.get("ports"), "autoremap": attrs.get("autoremap"),
                                 **{k: v for k, v in attrs.items() if k.startswith("_")}}
            for inner in attrs["ports"] if isinstance(attrs.get("ports"), dict) else ():
                locs[(where, USE_LOC + inner)] = doc.where((*path, "ports", inner))
        return placeholder

    def port_value(
        self, port: Port, given: Any, where: SourceLocation, locate: Locate | None = None
    ) -> Any:
        """Check one port binding as written; return what the spec keeps (NO_DEFAULT: bad).

        ``locate`` places a message literal's problems at their fields (see :meth:`literal`).
        """
        if not fits_port(port, given):
            return NO_DEFAULT  # the schema check words it (an unquoted {key}, a 1.5 for an int)
        if port.naming is not Naming.VALUE:
            return self.entry_name(port, given, where)
        ref = entry_ref(given, port.name)
        if ref is not None:
            if not ENTRY_NAME.match(ref.name):
                self.report(where, f"port '{port.name}': '{given}' is not a valid entry name "
                            "(letters, digits and '_', not starting with a digit)")
                return NO_DEFAULT
            return given
        if port.direction is not Direction.INPUT:
            if isinstance(given, str):
                self.report(where, f"{port.direction.value} port '{port.name}' must be bound "
                            f"to an entry ('{{key}}'), got '{given}'")
            return NO_DEFAULT
        return self.literal(port.type, given, where, f"port '{port.name}'", locate)

    def entry_name(self, port: Port, given: str, where: SourceLocation) -> Any:
        """Check a port whose text names an entry; return it as ``{name}`` (NO_DEFAULT: bad)."""
        ref = entry_ref(given)
        if ref is not None and port.naming is Naming.BARE_NAME:
            self.report(where, f"port '{port.name}' names its entry without braces: write "
                        f"'{ref.name}' (BT.CPP would read '{given}' as the entry whose name "
                        f"'{ref.name}' holds, which cannot be resolved before running)")
            return NO_DEFAULT
        if ref is None:
            root = given.startswith("@")
            ref = entry_ref(f"{{{'@' if root else ''}{given[1:] if root else given}}}")
        if ref is None or not ENTRY_NAME.match(ref.name):
            self.report(where, f"port '{port.name}': '{given}' is not a valid entry name "
                        "(letters, digits and '_', not starting with a digit)")
            return NO_DEFAULT
        return str(ref)

    def param_value(self, name: str, given: Any, where: SourceLocation) -> bool:
        """Report a ``{key}`` given to a param that is not a port; return whether it was."""
        if entry_ref(given) is None:
            return False
        self.report(where, f"'{name}' is a param, not a port: it cannot be bound to the "
                    f"entry '{given}'")
        return True

    # -- resolution in a scope ----------------------------------------------------------
    def bind_ports(
        self, spec: NodeSpec, ports: tuple[Port, ...], scope: DataScope,
        locs: dict[tuple[SourceLocation, str], Any],
    ) -> None:
        """Resolve a node's ports in ``scope`` into ``spec.bindings``; note reads and writes.

        A leaf's ports, and those of BT.CPP's nodes that use the blackboard
        (:mod:`.control_kinds`).
        """
        who = f"{spec.name} ({spec.kind})" if spec.name != spec.kind else spec.kind
        for port in ports:
            written = port.name in spec.ports
            given = spec.ports[port.name] if written else port.default
            where = locs.get((spec.location, PORT_LOC + port.name), spec.location)
            ref = entry_ref(given, port.name)
            if ref is None:
                spec.bindings[port.name] = PortBinding(port, value=given)
                continue
            what = f"port '{port.name}' of {who}" + ("" if written else f" (default {given})")
            shown = "" if port.naming is Naming.VALUE else str(ref)[1:-1]  # as written: x
            key = self.entries.resolve(scope, ref, where, what, shown)
            if key is None:
                continue
            if port.direction.reads:
                self.entries.read(key, port.type, where, what)
            if port.direction.writes:
                self.entries.write(key, port.type, where, what)
            spec.bindings[port.name] = PortBinding(port, key=key)
        if spec.kind in COPIES:
            self.copies.append(spec)

    def insertion(
        self, use: NodeSpec, definition: tuple[dict[str, Port] | None, dict[str, Declared] | None],
        uid: str, parent: DataScope, locs: dict[tuple[SourceLocation, str], Any],
    ) -> DataScope:
        """Return the scope of one subtree insertion; note its remaps and initial values.

        Args:
            use: The ``subtree:`` node (its attrs: ``ports``, ``autoremap``).
            definition: The definition's ports and its ``blackboard:`` entries (each None
                when it declares none).
            uid: The insertion's uid.
            parent: The scope it is inserted in.
            locs: Where each written value stands.
        """
        ports, local = definition
        name = use.name
        prefix = f"/{_UNSAFE.sub('_', name)}@{uid.replace('.', '_')}"
        declared = None
        if ports is not None or local is not None:
            declared = {p.name: Declared(p.name, p.type, caller_sets=False)
                        for p in (ports or {}).values()}
            declared.update(local or {})
        scope = DataScope(prefix, f"subtree '{name}'", declared, parent=parent,
                          autoremap=use.attrs.get("autoremap") is True, local=set(local or ()))
        given = use.attrs.get("ports")
        for inner, value in (given if isinstance(given, dict) else {}).items():
            where = locs.get((use.location, USE_LOC + inner), use.location)
            port = ports.get(inner) if ports is not None else None
            if ports is not None and port is None:
                self.report(where, f"subtree '{name}' has no port '{inner}'"
                            + (did_you_mean(inner, ports) or f" (its ports: {', '.join(ports)})"))
                continue
            self.remap(scope, inner, value, port, where)
        for key_name, decl in (local or {}).items():
            self.entries.declare(f"{prefix}/{key_name}", decl)
        for port in (ports or {}).values():
            if port.name in scope.remap or port.name in scope.local:
                continue
            key = scope.key(port.name)
            if key is None:
                continue
            own = key.startswith(prefix + "/") and entry_ref(port.default) is None
            initial = port.default if own else NO_DEFAULT
            self.entries.declare(key, Declared(port.name, port.type, initial, port.description,
                                               None, caller_sets=False))
        return scope

    def remap(
        self, scope: DataScope, inner: str, value: Any, port: Port | None, where: SourceLocation
    ) -> None:
        """Remap one inner name of a subtree insertion to a parent entry or a literal."""
        ref = entry_ref(value, inner)
        what = f"port '{inner}' of {scope.label}"
        if ref is not None:
            if not ENTRY_NAME.match(ref.name):
                self.report(where, f"{what}: '{value}' is not a valid entry name")
                return
            key = self.entries.resolve(scope.parent or scope, ref, where, what)
            scope.remap[inner] = key
            if key is None:
                return
            if port is not None:
                self.entries.declare(key, Declared(inner, port.type, NO_DEFAULT, port.description,
                                                   where, caller_sets=False))
            return
        if port is not None:
            value = self.literal(port.type, value, where, what)
            if value is NO_DEFAULT:
                return
        scope.local.add(inner)
        self.entries.set_initial(f"{scope.prefix}/{inner}", value)

    # -- after the walk -----------------------------------------------------------------
    def check_copies(self, locs: dict[tuple[SourceLocation, str], Any]) -> None:
        """Type what a copying node (SetBlackboard) writes by its destination's declaration.

        As BT.CPP parses a literal into a destination entry of another type than a
        string, a literal is converted to the declared type (reported when it does not
        convert; a message's text form, ``1.0;2.0;0.0``, becomes a message literal); a
        copied entry's declared type must agree with the destination's.
        """
        for spec in self.copies:
            source, destination = COPIES[spec.kind]
            value, target = spec.bindings.get(source), spec.bindings.get(destination)
            if value is None or target is None or target.key is None:
                continue
            declared = self.entries.declared.get(target.key)
            if not declared or declared[0].type == "any":
                continue
            type_ = declared[0].type
            where = locs.get((spec.location, PORT_LOC + source), spec.location)
            if value.key is None and value.value is not NO_DEFAULT and (
                    type_ in BASIC_TYPES or is_message(type_)):
                converted = self.literal(type_, value.value, where, f"port '{source}' of "
                                         f"{spec.kind}, written to '{target.key[1:]}' "
                                         f"(declared {type_})")
                if converted is not NO_DEFAULT:
                    spec.bindings[source] = PortBinding(value.port, value=converted)
            elif value.key is not None:
                other = self.entries.declared.get(value.key)
                if other and not compatible(other[0].type, type_):
                    self.report(where, f"{spec.kind} copies '{value.key[1:]}' (declared "
                                f"{other[0].type}) to '{target.key[1:]}' (declared {type_})")
