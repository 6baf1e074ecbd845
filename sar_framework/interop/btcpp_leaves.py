"""The state of one BT.CPP import, and the conversion of its leaves.

:class:`LeafImporter` holds what :mod:`.btcpp_import` gathers while it walks a file: the
problems and warnings, the drafts of unknown leaves and every blackboard use. It converts
the leaves: a registered plugin's attributes become params (converted to the declared
types) or port bindings; any other leaf becomes a :class:`~.btcpp_scaffold.LeafDraft`.
The walk of the tree itself (:meth:`LeafImporter.node`) is the subclass's.
"""

from __future__ import annotations

from typing import Any

from sar_framework.engine.nodes.node_kinds import AttrType
from sar_framework.engine.plugin import PluginSpec
from sar_framework.engine.registry import Registry
from sar_framework.interop import mapping
from sar_framework.interop.btcpp_entries import TreeUses, Use, entry_key
from sar_framework.interop.btcpp_file import BtcppFile
from sar_framework.interop.btcpp_models import NodeModel, PortModel, convert_literal, plugin_ports
from sar_framework.interop.btcpp_scaffold import LeafDraft
from sar_framework.interop.xml_source import Element, Problem

__all__ = ["LeafImporter"]


class LeafImporter:
    """What one import gathers, and the conversion of its leaves.

    Args:
        source: The file's trees and models.
        registry: The plugins leaves may name.
    """

    def __init__(self, source: BtcppFile, registry: Registry) -> None:
        self.source = source
        self.file = ""
        self.tree = ""
        self.registry = registry
        self.problems: list[Problem] = []
        self.drafts: dict[str, LeafDraft] = {}
        self.warnings: list[Problem] = []
        self.subtree_bodies: dict[str, list[dict[str, Any]]] = {}
        self.at = ""  # the node whose uses are being recorded (file:line:col)
        #: (tree, draft, attributes set, where) for every use of an unknown leaf.
        self.draft_uses: list[tuple[str, LeafDraft, set[str], str]] = []
        self.uses: dict[str, TreeUses] = {}
        self.literals: list[tuple[dict[str, Any], str, str, LeafDraft]] = []
        #: Tree ID -> the initial values its exported wrapper sets (see .btcpp_blackboard).
        self.initial: dict[str, dict[str, Any]] = {}

    def problem(self, element: Element, message: str) -> None:
        """Report ``message`` at ``element``."""
        self.problems.append(Problem(self.file, element.line, element.column, message))

    def use(self, entry: str, port: PortModel | None, node: str, name: str) -> None:
        """Record port ``name`` bound to ``{entry}`` (``{=}``: the entry named like it)."""
        direction = port.direction if port is not None else "inout"
        self.uses[self.tree].uses.append(Use(
            name if entry == "=" else entry, direction != "output", direction != "input",
            port.type if port is not None else "any", node, self.at))

    def node(self, element: Element) -> dict[str, Any] | None:
        """Convert one element and its children (the subclass walks the tree)."""
        raise NotImplementedError

    def default_uses(self) -> None:
        """Record the entries scaffolded ports use by default where the file leaves them."""
        for tree, draft, given, at in self.draft_uses:
            for port in draft.ports():
                entry = entry_key(port.default or "")
                if entry is None or port.name in given:
                    continue
                entry = port.name if entry == "=" else entry
                self.uses[tree].uses.append(Use(
                    entry, port.direction != "output", port.direction != "input", port.type,
                    f"<{draft.tag}> port '{port.name}' (its default)", at))

    def refuse(self, element: Element, message: str) -> None:
        """Report ``element``; still convert its children, to report their problems too."""
        self.problem(element, message)
        for child in element.children:
            self.node(child)

    def unknown(self, element: Element, tag: str, ports: dict[str, str],
                alias: str | None = None) -> dict[str, Any] | None:
        """Keep a leaf no plugin is registered for, described by its draft (``alias``: name)."""
        model: NodeModel | None = self.source.models.get(tag)
        if element.children or (model is not None and not model.is_leaf):
            what = f"a {model.category} node" if model is not None else "a node with children"
            self.refuse(element, f"<{tag}> is {what} this framework has no kind for; only "
                        "unknown leaves can be scaffolded (see docs/reference/btcpp-interop.md)")
            return None
        draft = self.drafts.get(tag)
        if draft is None:
            where = Problem(self.file, element.line, element.column, "")
            draft = self.drafts[tag] = LeafDraft(tag, where, model, plugin=alias or tag)
        draft.uses += 1
        self.draft_uses.append((self.tree, draft, set(ports), self.at))
        body: dict[str, Any] = {}
        for key, text in ports.items():
            if key == "name":
                body[key] = text
                continue
            if model is not None and model.port(key) is None:
                self.problem(element, f"<{tag}> has no port '{key}' in its model "
                             f"({model.where.file}:{model.where.line}); BT.CPP refuses a port "
                             "that providedPorts() does not declare")
                continue
            draft.use(key, text)
            entry = entry_key(text)
            if entry is not None:
                self.use(entry, model.port(key) if model is not None else None,
                         f"<{tag}> port '{key}'", key)
                body[key] = text
            else:
                body[key] = text
                self.literals.append((body, key, text, draft))
        return {draft.plugin: body}

    def leaf(self, element: Element, tag: str, plugin: PluginSpec,
             ports: dict[str, str]) -> dict[str, Any] | None:
        """Convert a registered plugin's leaf: params to their types, ports as bound."""
        if element.children:
            self.problem(element, f"<{tag}> is a leaf plugin: it cannot have children")
        declared = plugin_ports(plugin)
        body: dict[str, Any] = {}
        for key, text in ports.items():
            param = plugin.param(key)
            if key in ("name", "id"):
                body[key] = text
            elif key in declared:
                entry = entry_key(text)
                if entry is not None:
                    self.use(entry, declared[key], f"<{tag}> port '{key}'", key)
                    body[key] = text
                else:
                    body[key] = convert_literal(text, declared[key].type)
            elif param is None:
                names = [p.name for p in plugin.params] + list(declared)
                self.problem(element, f"<{tag}> has no param or port '{key}' (it has: "
                             f"{', '.join(names) or 'none'})")
            elif entry_key(text) is not None:
                self.problem(element, f"'{key}' of <{tag}> is a param, not a port: it cannot "
                             f"read the blackboard entry '{text}'; give a value")
            elif param.ref is not None:
                body[key] = text
            else:
                kind = {str: AttrType.STRING, int: AttrType.INTEGER, float: AttrType.NUMBER,
                        bool: AttrType.BOOLEAN}[param.type]
                body[key] = self.value(element, key, text, kind)
        return {plugin.name: body}

    def value(self, element: Element, key: str, text: str, kind: AttrType) -> Any:
        """Convert an attribute's text to ``kind`` (the text itself on a reported problem)."""
        try:
            return mapping.attr_value(kind, key, text)
        except ValueError as exc:
            self.problem(element, str(exc))
            return text
