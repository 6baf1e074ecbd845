"""Import BehaviorTree.CPP 4 XML as a tree document of our format.

The main ``<BehaviorTree>`` becomes ``root``; every other one becomes an entry of
``subtrees`` and ``<SubTree ID="X"/>`` becomes ``subtree: X``. Nodes map back through
:mod:`.mapping`; a leaf's tag must name a registered plugin, and its attributes its
params (converted to the declared types). Everything that cannot be expressed
(blackboard ports ``{key}`` other than those of BT.CPP's blackboard nodes, scripts,
pre/post conditions, Nav2's DistanceController, ...) is reported as
``file:line:col: error: ...``, all at once. The document still needs our validator
(ids, references, ranges): see :func:`sar_framework.interop.commands.run_import`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import yaml

from sar_framework.engine.control_kinds import ENTRY_PORTS
from sar_framework.engine.node_kinds import KINDS, AttrType, NodeKind
from sar_framework.engine.plugin import PluginSpec
from sar_framework.engine.registry import Registry
from sar_framework.engine.spec import Category
from sar_framework.interop.mapping import BUILTIN_BY_ID, CUSTOM_KINDS, REFUSED, custom_ports
from sar_framework.interop.xml_source import Element, Problem

#: Attributes of BT.CPP nodes that carry no meaning for the tree (Groot2 metadata).
IGNORED_ATTRS = frozenset({"_description", "_uid", "_fullpath"})
#: v3-style explicit node elements: ``<Action ID="X"/>`` is ``<X/>``.
EXPLICIT_TAGS = frozenset({"Action", "Condition", "Control", "Decorator"})


@dataclass
class ImportResult:
    """What an import produced.

    Attributes:
        document: The tree document (format, name, subtrees, root), or None on problems.
        problems: Every problem found, in file order.
    """

    document: dict[str, Any] | None
    problems: list[Problem] = field(default_factory=list)


class _Importer:
    def __init__(self, file: str, registry: Registry, trees: dict[str, Element]) -> None:
        self.file = file
        self.registry = registry
        self.trees = trees
        self.problems: list[Problem] = []

    def problem(self, element: Element, message: str) -> None:
        self.problems.append(Problem(self.file, element.line, element.column, message))

    def node(self, element: Element) -> dict[str, Any] | None:
        tag = element.tag
        ports = {k: v for k, v in element.attrs.items() if k not in IGNORED_ATTRS}
        if tag in EXPLICIT_TAGS and "ID" in ports:
            tag = ports.pop("ID")
        for key, value in ports.items():
            if key.startswith("_"):
                self.problem(element, f"'{key}' on <{tag}>: BT.CPP pre/post conditions are "
                             "scripts on the blackboard, which this framework does not have")
            elif (value.strip().startswith("{") and value.strip().endswith("}")
                  and not (tag in KINDS and key in ENTRY_PORTS)):
                self.problem(element, f"port '{key}' of <{tag}> reads the blackboard entry "
                             f"'{value}'; this framework has no blackboard (leaves share "
                             "state by references to other leaves' ids): give a value")
        ports = {k: v for k, v in ports.items() if not k.startswith("_")}
        if tag == "SubTree":
            return self.subtree(element, ports)
        if tag in REFUSED:
            self.refuse(element, f"<{tag}> cannot be imported: {REFUSED[tag]}")
            return None
        if tag in BUILTIN_BY_ID:
            entry = BUILTIN_BY_ID[tag]
            try:
                attrs = {**dict(entry.fixed), **entry.from_ports(ports)}
            except ValueError as exc:
                self.problem(element, f"<{tag}>: {exc}")
                return None
            return self.branch(element, KINDS[entry.kind], ports.get("name"), attrs)
        if tag in CUSTOM_KINDS:
            kind = CUSTOM_KINDS[tag]
            attrs = {}
            for name, *_ in custom_ports(kind):
                if name in ports:
                    attrs[name] = self.value(element, name, ports[name], kind.attr(name).type)
            return self.branch(element, kind, ports.get("name"), attrs)
        plugin = self.registry.get(tag)
        if plugin is None:
            self.refuse(element, f"unknown node <{tag}>: neither a BT.CPP node we map nor a "
                        "registered plugin (see 'sar-tree plugins'; add yours with "
                        "--plugin-path)")
            return None
        return self.leaf(element, plugin, ports)

    def refuse(self, element: Element, message: str) -> None:
        """Report ``element``; still convert its children, to report their problems too."""
        self.problem(element, message)
        for child in element.children:
            self.node(child)

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

    def leaf(self, element: Element, plugin: PluginSpec,
             ports: dict[str, str]) -> dict[str, Any] | None:
        if element.children:
            self.problem(element, f"<{element.tag}> is a leaf plugin: it cannot have children")
        body: dict[str, Any] = {}
        for key, text in ports.items():
            param = plugin.param(key)
            if key in ("name", "id"):
                body[key] = text
            elif param is None:
                self.problem(element, f"<{element.tag}> has no param '{key}' (its params: "
                             f"{', '.join(p.name for p in plugin.params) or 'none'})")
            elif param.ref is not None:
                body[key] = text
            else:
                kind = {str: AttrType.STRING, int: AttrType.INTEGER, float: AttrType.NUMBER,
                        bool: AttrType.BOOLEAN}[param.type]
                body[key] = self.value(element, key, text, kind)
        return {plugin.name: body}

    def subtree(self, element: Element, ports: dict[str, str]) -> dict[str, Any] | None:
        name = ports.pop("ID", None)
        ports.pop("name", None)
        if name is None:
            self.problem(element, "<SubTree> needs an ID")
            return None
        if name not in self.trees:
            self.problem(element, f"<SubTree ID=\"{name}\">: no <BehaviorTree ID=\"{name}\"> in "
                         "this file (<include> is not supported)")
        if ports:
            self.problem(element, f"<SubTree ID=\"{name}\"> remaps the ports "
                         f"{', '.join(sorted(ports))}; our subtrees take no ports (leaves share "
                         "state by references)")
        return {"subtree": name}

    def value(self, element: Element, key: str, text: str, kind: AttrType) -> Any:
        try:
            if kind is AttrType.BOOLEAN:
                lowered = text.strip().lower()
                if lowered not in ("true", "false"):
                    raise ValueError
                return lowered == "true"
            if kind is AttrType.INTEGER:
                return int(text)
            if kind is AttrType.NUMBER:
                number = float(text)
                return int(number) if number.is_integer() and "." not in text else number
        except ValueError:
            self.problem(element, f"'{key}' must be a {kind.value}, got '{text}'")
            return text
        if kind is AttrType.STRINGS:
            return [part for part in text.split(";") if part]
        return text


def import_btcpp(root: Element, file: str, registry: Registry) -> ImportResult:
    """Turn a parsed BT.CPP 4 document into our tree document.

    Args:
        root: The parsed ``<root>`` element (:func:`.xml_source.read_xml`).
        file: The file name, for problems.
        registry: The plugins leaves must name.

    Returns:
        The document, or the problems.
    """
    here = Problem(file, root.line, root.column, "")
    if root.tag != "root":
        return ImportResult(None, [_at(here, f"expected <root>, got <{root.tag}>")])
    if root.attrs.get("BTCPP_format") != "4":
        return ImportResult(None, [_at(here, "only BehaviorTree.CPP v4 XML is read "
                                       "(<root BTCPP_format=\"4\">)")])
    trees: dict[str, Element] = {}
    importer = _Importer(file, registry, trees)
    for element in root.children:
        if element.tag == "BehaviorTree":
            trees[element.attrs.get("ID", "")] = element
        elif element.tag == "include":
            importer.problem(element, "<include> is not supported: put every tree in one file")
        elif element.tag != "TreeNodesModel":
            importer.problem(element, f"unexpected <{element.tag}> under <root>")
    main = root.attrs.get("main_tree_to_execute") or (next(iter(trees)) if len(trees) == 1
                                                      else None)
    if main not in trees:
        importer.problem(root, "which tree is the main one? set main_tree_to_execute="
                         f"(trees: {', '.join(trees) or 'none'})")
        return ImportResult(None, importer.problems)
    bodies: dict[str, Any] = {}
    for name, element in trees.items():
        if len(element.children) != 1:
            importer.problem(element, f"<BehaviorTree ID=\"{name}\"> must hold exactly one node")
            continue
        bodies[name] = importer.node(element.children[0])
    if importer.problems:
        return ImportResult(None, sorted(importer.problems, key=lambda p: (p.line, p.column)))
    document: dict[str, Any] = {"format": 1, "name": main}
    description = trees[main].attrs.get("_description")
    if description:
        document["description"] = description
    subtrees = {name: body for name, body in bodies.items() if name != main}
    if subtrees:
        document["subtrees"] = subtrees
    document["root"] = bodies[main]
    return ImportResult(document)


def _at(where: Problem, message: str) -> Problem:
    return Problem(where.file, where.line, where.column, message)


def document_yaml(document: dict[str, Any], source: str) -> str:
    """Format an imported document as a tree file (block style, leaves on one line)."""
    header = f"# Imported from {source} by 'sar-tree import'.\n"
    return header + yaml.safe_dump(document, sort_keys=False, default_flow_style=None,
                                   allow_unicode=True, width=100)
