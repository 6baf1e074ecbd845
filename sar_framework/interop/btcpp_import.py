"""Import BehaviorTree.CPP 4 XML as a tree document of our format.

The file's shape (several trees, the main one, includes, models) is read by
:mod:`.btcpp_file`. The main ``<BehaviorTree>`` becomes ``root``; every other one an
entry of ``subtrees``, and ``<SubTree ID="X" port="{key}" _autoremap="true"/>`` becomes
``subtree: {tree: X, ports: {port: "{key}"}, autoremap: true}`` (``subtree: X`` without
ports). Composites and decorators map back through :mod:`.mapping`. A leaf whose tag is
a registered plugin keeps its attributes as params (converted to the declared types) or
port bindings (``{key}`` or a literal); any other leaf is *unknown*: it is kept as it is
and described by a :class:`~.btcpp_scaffold.LeafDraft`, from which ``--scaffold`` writes a
plugin. Entries the main tree reads and nothing writes become declared ``blackboard:``
inputs (:mod:`.btcpp_entries`). Scripts and the pre/post-condition attributes are kept
as written, each compiled and its variables recorded as uses (:mod:`.btcpp_scripts`).
What cannot be expressed (the nodes :data:`.mapping.REFUSED` names, conditions on a
``<SubTree>``) is reported as ``file:line:col: error: ...``, all at once. The document
still needs our validator: see :func:`sar_framework.interop.commands.run_import`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from sar_framework.engine.nodes.control_kinds import ENTRY_PORTS
from sar_framework.engine.nodes.node_kinds import KINDS, AttrType, NodeKind
from sar_framework.engine.registry import Registry
from sar_framework.engine.spec import Category
from sar_framework.interop.btcpp_blackboard import scope_section, unwrap_initial, with_private
from sar_framework.interop.btcpp_entries import (
    Insertion,
    TreeUses,
    blackboard_declarations,
    caller_inputs,
    effective_uses,
    entry_key,
    subtree_definition,
)
from sar_framework.interop.btcpp_file import read_btcpp
from sar_framework.interop.btcpp_leaves import LeafImporter
from sar_framework.interop.btcpp_models import (
    NodeModel,
    PortModel,
    clashes,
    convert_literal,
    missing_ports,
)
from sar_framework.interop.btcpp_scaffold import LeafDraft
from sar_framework.interop.btcpp_scripts import script_uses, split_conditions
from sar_framework.interop.mapping import (
    BUILTIN_BY_ID,
    CUSTOM_KINDS,
    REFUSED,
    custom_ports,
    plugin_mapping,
)
from sar_framework.interop.xml_source import Element, Problem

#: Attributes of BT.CPP nodes that carry no meaning for the tree (Groot2 metadata).
IGNORED_ATTRS = frozenset({"_description", "_uid", "_fullpath"})
#: Prefix of the scaffolded plugin for a node whose model clashes with a registered plugin
#: of the same name (Nav2's ``Wait`` and ours).
ALIAS_PREFIX = "Btcpp"
#: v3-style explicit node elements: ``<Action ID="X"/>`` is ``<X/>``.
EXPLICIT_TAGS = frozenset({"Action", "Condition", "Control", "Decorator"})


@dataclass
class ImportResult:
    """What an import produced.

    Attributes:
        document: The tree document (format, name, blackboard, subtrees, root), or None
            on problems.
        problems: Every problem found, in file order.
        drafts: The unknown leaves, by tag, in first-use order (for ``--scaffold``).
        warnings: What was read, but differently than the file may mean.
    """

    document: dict[str, Any] | None
    problems: list[Problem] = field(default_factory=list)
    drafts: dict[str, LeafDraft] = field(default_factory=dict)
    warnings: list[Problem] = field(default_factory=list)


class _Importer(LeafImporter):
    """Converts the trees of one BT.CPP file, composites, decorators and subtree uses."""

    def convert(self, tree: str) -> Any:
        """Convert the tree ``tree`` (None on a problem, reported)."""
        where = self.source.trees[tree]
        self.file, self.tree = where.file, tree
        self.uses[tree] = TreeUses()
        if len(where.element.children) != 1:
            self.problem(where.element, f"<BehaviorTree ID=\"{tree}\"> must hold exactly one "
                         f"node, it holds {len(where.element.children)} (BT.CPP refuses it)")
            return None
        top = where.element.children[0]
        unwrapped = unwrap_initial(top)
        if unwrapped is not None:
            top, self.initial[tree] = unwrapped
            self.at = f"{self.file}:{where.element.line}:{where.element.column}"
            for name in self.initial[tree]:
                self.use(name, PortModel("code", "output", "any"),
                         f"<BehaviorTree ID=\"{tree}\">'s initial values", "code")
        return self.node(top)

    def node(self, element: Element) -> dict[str, Any] | None:
        """Convert one element and its children (None on a problem, reported)."""
        self.at = f"{self.file}:{element.line}:{element.column}"
        tag = element.tag
        ports = {k: v for k, v in element.attrs.items() if k not in IGNORED_ATTRS}
        if tag in EXPLICIT_TAGS and "ID" in ports:
            tag = ports.pop("ID")
        ports, conditions, dropped = split_conditions(tag, ports)
        self.warnings += [Problem(self.file, element.line, element.column, message, "warning")
                          for message in dropped]
        if tag == "SubTree":  # its conditions: scripts of the parent's scope
            if not self.scripts(element, tag, conditions):
                return None
            found = self.subtree(element, ports)
            if found is not None and conditions:
                body = found["subtree"]
                found["subtree"] = {**(body if isinstance(body, dict) else {"tree": body}),
                                    **conditions}
            return found
        if not self.scripts(element, tag, conditions):
            return None
        found = self.node_body(element, tag, ports)
        if found is not None and conditions:  # written before the children
            body = next(iter(found.values()))
            below = {key: body.pop(key) for key in ("child", "children") if key in body}
            body.update({**conditions, **below})
        return found

    def scripts(self, element: Element, tag: str, texts: dict[str, str]) -> bool:
        """Compile each script; record its variables as uses; False on a syntax error."""
        uses, errors = script_uses(tag, texts)
        for message in errors:
            self.problem(element, message)
        for name, port, who in uses:
            self.use(name, port, who, port.name)
        return not errors

    def node_body(self, element: Element, tag: str,
                  ports: dict[str, str]) -> dict[str, Any] | None:
        """The node ``{kind: body}`` of ``element`` (its conditions are added by the caller)."""
        ports.pop("_autoremap", None)
        if tag in REFUSED:
            self.refuse(element, f"<{tag}> cannot be imported: {REFUSED[tag]}")
            return None
        mapped = BUILTIN_BY_ID.get(tag) or plugin_mapping(tag, self.registry)
        kind = self.kind_of(mapped.kind) if mapped is not None else CUSTOM_KINDS.get(tag)
        for key, value in ports.items() if kind is not None else ():
            if entry_key(value) is None:
                continue
            attr = kind.attr(key)  # type: ignore[union-attr]
            if key in ENTRY_PORTS and tag in KINDS:
                self.use(entry_key(value) or "", None, f"<{tag}> port '{key}'", key)
            elif attr is None or attr.port is None:
                self.problem(element, f"port '{key}' of <{tag}> reads the blackboard entry "
                             f"'{value}'; ours takes a fixed value here: give one")
                return None
        if mapped is not None:
            entry = mapped
            code = {k: v for k, v in ports.items() if kind is not None
                    and getattr(kind.attr(k), "type", None) is AttrType.SCRIPT}
            if not self.scripts(element, tag, code):
                return None
            try:
                attrs = {**dict(entry.fixed), **entry.from_ports(ports)}
            except ValueError as exc:
                self.problem(element, f"<{tag}>: {exc}")
                return None
            self.kind_uses(self.kind_of(entry.kind), tag, attrs)
            return self.branch(element, self.kind_of(entry.kind), ports.get("name"), attrs)
        if tag in CUSTOM_KINDS:
            kind = CUSTOM_KINDS[tag]
            attrs = {}
            for name, *_ in custom_ports(kind):
                if name in ports:
                    attrs[name] = self.value(element, name, ports[name], kind.attr(name).type)
            return self.branch(element, kind, ports.get("name"), attrs)
        plugin = self.registry.get(tag)
        model = self.source.models.get(tag)
        if plugin is None:
            return self.unknown(element, tag, ports)
        if model is None or not clashes(plugin, model):
            return self.leaf(element, tag, plugin, ports)
        alias = ALIAS_PREFIX + tag
        if tag not in self.drafts:
            self.warnings.append(Problem(
                self.file, element.line, element.column, f"<{tag}> is not the registered "
                f"plugin '{tag}': its model ({model.where.file}:{model.where.line}) declares "
                f"ports the plugin lacks ({', '.join(missing_ports(plugin, model))}); "
                f"scaffolded as '{alias}'", "warning"))
        return self.unknown(element, tag, ports, alias)

    def kind_of(self, key: str) -> NodeKind:
        """The declaration of a node kind, built in or a plugin's."""
        return KINDS.get(key) or self.registry.kind(key)  # type: ignore[return-value]

    def kind_uses(self, kind: NodeKind, tag: str, attrs: dict[str, Any]) -> None:
        """Record the entries a control node's port attributes are bound to."""
        for name, value in attrs.items():
            attr = kind.attr(name)
            entry = entry_key(value) if isinstance(value, str) else None
            if attr is None or attr.port is None or entry is None:
                continue
            port = attr.port
            self.use(entry, PortModel(name, port.direction.value, port.type),
                     f"<{tag}> port '{name}'", name)

    def branch(self, element: Element, kind: NodeKind, name: str | None,
               attrs: dict[str, Any]) -> dict[str, Any] | None:
        children = [self.node(child) for child in element.children]
        body: dict[str, Any] = {"name": name} if name else {}
        body.update(attrs)
        if kind.category is Category.LEAF:
            if children:
                self.problem(element, f"<{element.tag}> is a leaf: it cannot have children")
                return None
        elif kind.category is Category.DECORATOR:
            if len(children) != 1:
                self.problem(element, f"<{element.tag}> is a decorator: it needs exactly one "
                             f"child, got {len(children)}")
                return None
            body["child"] = children[0]
        else:
            if not children:
                self.problem(element, f"<{element.tag}> has no children")
                return None
            body["children"] = children
        return {kind.key: body}

    def subtree(self, element: Element, ports: dict[str, str]) -> dict[str, Any] | None:
        name = ports.pop("ID", None)
        ports.pop("name", None)
        autoremap_text = ports.pop("_autoremap", "false").strip().lower()
        if autoremap_text not in ("true", "false", "1", "0"):
            self.problem(element, f"_autoremap=\"{autoremap_text}\" is not a boolean")
        autoremap = autoremap_text in ("true", "1")
        if name is None:
            self.problem(element, "<SubTree> needs an ID")
            return None
        if name not in self.source.trees:
            self.problem(element, f"<SubTree ID=\"{name}\">: no <BehaviorTree ID=\"{name}\"> "
                         f"in this file or its includes (trees: {', '.join(self.source.trees)})")
            return None
        model = self.source.models.get(name)
        if model is not None and model.category == "SubTree" and not autoremap:
            for port in model.ports:
                if port.name in ports:
                    continue
                if port.default is None:
                    self.problem(element, f"<SubTree ID=\"{name}\"> does not remap the port "
                                 f"'{port.name}' its model declares mandatory (BT.CPP refuses "
                                 "it)")
                else:
                    ports[port.name] = port.default
        self.uses[self.tree].insertions.append(Insertion(name, dict(ports), autoremap))
        if not ports and not autoremap:
            return {"subtree": name}
        body: dict[str, Any] = {"tree": name}
        if ports:
            body["ports"] = ports
            self.subtree_bodies.setdefault(name, []).append(body)
        if autoremap:
            body["autoremap"] = True
        return {"subtree": body}

def import_btcpp(root: Element, file: str, registry: Registry, *, main: str | None = None,
                 models: dict[str, NodeModel] | None = None) -> ImportResult:
    """Turn a parsed BT.CPP 4 document into our tree document.

    Args:
        root: The parsed ``<root>`` element (:func:`.xml_source.read_xml`).
        file: The file name, for problems and includes.
        registry: The plugins leaves may name; any other leaf is a draft.
        main: The main tree when the file does not say (``--main``).
        models: Node models from palettes (``--nodes-model``).

    Returns:
        The document and the drafts, or the problems.
    """
    source = read_btcpp(root, file, main=main, models=models)
    if source.main is None:
        return ImportResult(None, source.problems)
    importer = _Importer(source, registry)
    importer.problems.extend(source.problems)
    bodies = {tree: importer.convert(tree) for tree in source.trees}
    for body, key, text, draft in importer.literals:
        body[key] = convert_literal(text, draft.port_type(key))
    importer.default_uses()
    drafts = importer.drafts
    if importer.problems:
        return ImportResult(None, sorted(importer.problems, key=lambda p: (p.file, p.line,
                                                                           p.column)), drafts,
                            importer.warnings)
    main_tree = source.main
    document: dict[str, Any] = {"format": 1, "name": main_tree}
    description = source.trees[main_tree].element.attrs.get("_description")
    if description:
        document["description"] = description
    main_uses = effective_uses(main_tree, importer.uses)
    section = scope_section(source.declarations.get(main_tree), importer.initial.get(main_tree))
    if section is not None:
        document["blackboard"] = section
    elif caller_inputs(main_uses):
        document["blackboard"] = blackboard_declarations(main_uses, Path(file).name)
    subtrees = {}
    for name, body in bodies.items():
        if name != main_tree:
            insertions = [i for uses in importer.uses.values() for i in uses.insertions
                          if i.tree == name]
            subtrees[name] = subtree_definition(
                name, body, importer.uses, insertions=insertions,
                uses_written=importer.subtree_bodies.get(name, []),
                model=source.models.get(name), source=Path(source.trees[name].file).name)
            private = scope_section(source.declarations.get(name), importer.initial.get(name))
            if private is not None:
                subtrees[name] = with_private(subtrees[name], body, private)
    if subtrees:
        document["subtrees"] = subtrees
    document["root"] = bodies[main_tree]
    return ImportResult(document, [], drafts, importer.warnings)

