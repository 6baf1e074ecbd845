"""Export a validated tree as BehaviorTree.CPP 4 XML (``BTCPP_format="4"``), Groot2-ready.

The document holds one ``<BehaviorTree>`` for the tree, one per subtree it uses (each use
becomes ``<SubTree ID="..."/>``), and a ``<TreeNodesModel>`` declaring every leaf plugin
with its params as input ports (type, default, description) plus an ``id`` port, and
every custom ``Sar...`` node (see :mod:`.mapping`) and every Nav2 node used (as Nav2's
palette declares them; BT.CPP's own nodes need no model); a leaf's ports
(``@leaf(ports=...)``) are declared with their direction (``input_port``,
``output_port``, ``inout_port``), C++ type (none for ``any``), default and description.
Leaf params and port bindings (``{key}`` or literals) are written when they differ from
the declared default, and a leaf's ``name`` when it is not the plugin name (BT.CPP's
default too); reference params carry the referenced leaf's ``id``. Each scope's
``blackboard:`` section is written as :mod:`.btcpp_blackboard` says: a run-once ``Script``
of its initial values before its root, and a ``<Blackboard>`` element of its declarations.
The tree's ``plugins:`` become a ``<Plugins>`` element (:mod:`.btcpp_plugins`).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Sequence
from pathlib import Path

from sar_framework.engine.nodes.node_kinds import KINDS
from sar_framework.engine.plugin import REQUIRED, PluginSpec
from sar_framework.engine.ports import NO_DEFAULT
from sar_framework.engine.registry import Registry
from sar_framework.engine.spec import Category, NodeSpec, TreeSpec
from sar_framework.interop.btcpp_blackboard import declarations_element, with_initial
from sar_framework.interop.btcpp_palette import kind_model, leaf_model
from sar_framework.interop.btcpp_plugins import plugins_element
from sar_framework.interop.btcpp_scripts import condition_scripts
from sar_framework.interop.mapping import (
    builtin_for,
    custom_id,
    custom_ports,
    port_text,
    same_ids,
)


class _Exporter:
    """Walks a spec once, collecting subtree definitions and the models used."""

    def __init__(self, registry: Registry, spec: TreeSpec) -> None:
        self.registry = registry
        self.declarations = spec.declarations
        self.subtrees: dict[str, ET.Element] = {}
        self.leaf_models: dict[str, PluginSpec] = {}
        self.custom_models: set[str] = set()
        self.own_models: set[str] = set()

    def element(self, node: NodeSpec, *, inside: str | None = None) -> ET.Element:
        if node.subtree is not None and node.subtree != inside:
            if node.subtree not in self.subtrees:
                self.subtrees[node.subtree] = ET.Element("placeholder")  # recursion guard
                self.subtrees[node.subtree] = with_initial(
                    self.element(node, inside=node.subtree),
                    self.declarations.get(node.subtree, {}))
            conditions = condition_scripts(node.use.scripts) if node.use is not None else {}
            return ET.Element("SubTree", {"ID": node.subtree, **insertion_ports(node),
                                          **conditions})
        element = self.node(node)
        for name, text in condition_scripts(node.scripts).items():
            element.set(name, text)
        return element

    def node(self, node: NodeSpec) -> ET.Element:
        if node.category is Category.LEAF and node.kind not in KINDS:
            return self.leaf(node)
        plugin_kind = self.registry.kind(node.kind)
        kind = KINDS.get(node.kind) or plugin_kind
        builtin = same_ids(kind) if plugin_kind is not None else builtin_for(node.kind,
                                                                             node.attrs)
        if plugin_kind is not None:  # a plugin's kind: declared in the models
            self.own_models.add(node.kind)
        if builtin is not None:
            tag, ports = builtin.btcpp_id, builtin.to_ports(node.attrs)
        else:
            tag = custom_id(kind)
            self.custom_models.add(node.kind)
            ports = {name: port_text(node.attrs[name]) for name, *_ in custom_ports(kind)
                     if node.attrs.get(name) is not None}
        element = ET.Element(tag, {"name": node.name, **ports})
        element.extend(self.element(child) for child in node.children)
        return element

    def leaf(self, node: NodeSpec) -> ET.Element:
        plugin = self.registry.get(node.kind)
        if plugin is None:
            raise KeyError(f"plugin '{node.kind}' is not in the registry")
        self.leaf_models[plugin.name] = plugin
        ports = {"name": node.name} if node.name != plugin.name else {}
        if node.id is not None:
            ports["id"] = node.id
        for param in plugin.params:
            value = node.attrs.get(param.name)
            if value is not None and (param.default is REQUIRED or value != param.default):
                ports[param.name] = port_text(value)
        for port in plugin.ports:
            value = node.ports.get(port.name)
            if value is not None and (port.default is NO_DEFAULT or value != port.default):
                ports[port.name] = port_text(value)
        return ET.Element(node.kind, ports)

    def models(self) -> ET.Element:
        root = ET.Element("TreeNodesModel")
        for plugin in sorted(self.leaf_models.values(), key=lambda p: p.name):
            leaf_model(plugin, root, description=False)
        for key in sorted(self.custom_models | self.own_models):
            kind = KINDS.get(key) or self.registry.kind(key)
            assert kind is not None, "a node kind the tree holds"
            ident = kind.key if key in self.own_models else custom_id(kind)
            kind_model(kind, root, ident=ident, description=False)
        return root


def insertion_ports(node: NodeSpec) -> dict[str, str]:
    """The attributes of a subtree insertion: its ports as written, then ``_autoremap``."""
    ports = {name: port_text(value) for name, value in (node.insertion.get("ports") or {}).items()}
    if node.insertion.get("autoremap"):
        ports["_autoremap"] = "true"
    return ports


def export_btcpp(spec: TreeSpec, registry: Registry, *, folder: Path | None = None,
                 extra_plugins: Sequence[str] = ()) -> str:
    """Return the tree as BehaviorTree.CPP 4 XML text.

    Args:
        spec: A validated tree.
        registry: The plugins it was validated against (for the leaf port models).
        folder: Where the XML goes: the tree's plugin files are written relative to it
            (:mod:`.btcpp_plugins`); None writes them absolute.
        extra_plugins: Plugins the tree was validated with besides its own (absolute
            paths or module names, as ``--plugin-path`` gave them).

    Returns:
        The XML document, indented, with an XML declaration.
    """
    exporter = _Exporter(registry, spec)
    main = with_initial(exporter.element(spec.root), spec.declarations.get("", {}))
    root = ET.Element("root", {"BTCPP_format": "4", "main_tree_to_execute": spec.name})
    plugins = plugins_element([*spec.plugin_paths, *extra_plugins], folder)
    if plugins is not None:
        root.append(plugins)
    tree = ET.SubElement(root, "BehaviorTree", {"ID": spec.name})
    if spec.description:
        tree.set("_description", spec.description)
    tree.append(main)
    for name, body in exporter.subtrees.items():
        ET.SubElement(root, "BehaviorTree", {"ID": name}).append(body)
    for name, scope in [(spec.name, ""), *((n, n) for n in exporter.subtrees)]:
        declared = declarations_element(name, spec.declarations.get(scope, {}))
        if declared is not None:
            root.append(declared)
    root.append(exporter.models())
    ET.indent(root, space="  ")
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, "unicode") + "\n"
