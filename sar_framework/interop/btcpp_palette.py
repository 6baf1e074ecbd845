"""Our palette: a Groot2 ``<TreeNodesModel>`` of every node kind (``sar-tree palette``).

Nav2 ships ``nav2_tree_nodes.xml`` so that Groot2 can show and edit trees of its nodes;
this writes the same kind of file for everything a tree can hold:

- every registered leaf (built-in leaves, ``sar_plugins.nav2``, installed entry points
  and ``--plugin-path`` plugins): an ``<Action>`` or a ``<Condition>``
  (``@leaf(condition=True)``) whose ports are, in BT.CPP's order of a model: the ``id``
  attribute, every param (an input port: a tree file sets it as an XML attribute) and
  every port, each with its C++ type, default and description as text;
- every control, decorator and built-in leaf kind of BT.CPP and Nav2 (``Sequence``,
  ``RecoveryNode``, ``Script``...), under its BT.CPP ID, with its ports as BT.CPP's (or
  Nav2's) ``providedPorts()`` declares them; its children and its pre- and
  post-conditions (``_skipIf``...) are not ports;
- every py_trees kind that BT.CPP has no node for (``one_shot`` latching on success only,
  ``parallel``...) as the custom node ``Sar<ClassName>`` the export writes then
  (:mod:`.mapping`), with its attributes as ports;

then each one's description in ``<description>`` (BT.CPP 4's model schema), followed, for a
py_trees kind, by how it ticks unlike BT.CPP's nodes (its declared ``differences``).
``sar-tree export`` writes the models of the nodes a tree uses with the same functions,
and the importer reads them back.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from typing import Any

from sar_framework.engine.nodes.control_kinds import CONTROL_KINDS
from sar_framework.engine.nodes.kind_model import AttrType, NodeKind
from sar_framework.engine.nodes.node_kinds import PY_TREES_KINDS, SCRIPT_KINDS
from sar_framework.engine.param import REQUIRED
from sar_framework.engine.plugin import PluginSpec
from sar_framework.engine.ports import NO_DEFAULT
from sar_framework.engine.registry import Registry
from sar_framework.engine.spec import Category
from sar_framework.interop.btcpp_models import cpp_type
from sar_framework.interop.mapping import always_builtin, custom_id, port_text

#: A leaf param's type -> the C++ type its model port declares.
CPP_TYPES = {str: "std::string", int: "int", float: "double", bool: "bool"}
#: The id every leaf accepts.
ID_PORT_TEXT = "Unique id of this leaf; other leaves' reference ports name it."
#: Port direction -> model element.
PORT_ELEMENTS = {"input": "input_port", "output": "output_port", "inout": "inout_port"}
#: A kind's category -> its model element (a built-in leaf kind is an Action, but for
#: the one BT.CPP registers as a condition).
KIND_ELEMENTS = {Category.COMPOSITE: "Control", Category.DECORATOR: "Decorator",
                 Category.LEAF: "Action"}
CONDITION_KINDS = frozenset({"ScriptCondition"})
#: A kind's literal attribute type -> the C++ type of its model port (a list: 'a;b;c').
KIND_CPP_TYPES = {AttrType.STRING: "std::string", AttrType.INTEGER: "int",
                  AttrType.NUMBER: "double", AttrType.BOOLEAN: "bool",
                  AttrType.STRINGS: "std::string", AttrType.SCRIPT: "std::string"}


def model_port(model: ET.Element, name: str, cpp: str | None, default: Any, text: str, *,
               element: str = "input_port") -> None:
    """Append one port element to a node model."""
    attrs = {"name": name}
    if cpp is not None:
        attrs["type"] = cpp
    if default is not None:
        attrs["default"] = port_text(default)
    ET.SubElement(model, element, attrs).text = text or None


def leaf_model(plugin: PluginSpec, parent: ET.Element, *, description: bool = True) -> None:
    """Append the model of one leaf plugin to ``parent`` (a ``<TreeNodesModel>``).

    Args:
        plugin: The leaf.
        parent: The element to append to.
        description: Whether to write the leaf's ``<description>``.
    """
    category = "Condition" if plugin.condition else "Action"
    model = ET.SubElement(parent, category, {"ID": plugin.name})
    model_port(model, "id", "std::string", None, ID_PORT_TEXT)
    for param in plugin.params:
        cpp = "std::string" if param.ref is not None else CPP_TYPES[param.type]
        text = param.description or (f"id of a {param.ref} leaf" if param.ref else "")
        default = None if param.default is REQUIRED else param.default
        model_port(model, param.name, cpp, default, text)
    for port in plugin.ports:
        default = None if port.default is NO_DEFAULT else port.default
        model_port(model, port.name, cpp_type(port.type), default, port.description,
                   element=PORT_ELEMENTS[port.direction.value])
    if description and plugin.description:
        ET.SubElement(model, "description").text = plugin.description


def kind_model(kind: NodeKind, parent: ET.Element, *, ident: str | None = None,
               description: bool = True) -> None:
    """Append the model of one node kind to ``parent`` (a ``<TreeNodesModel>``).

    Its ports are its attributes but ``name``, the children and the pre- and
    post-conditions: a blackboard port with its direction and type, a literal as an input
    port. An empty string default means "not given" (Nav2's frames: the navigator's
    then), so the model declares no default, as Nav2's palette.

    Args:
        kind: The node kind.
        parent: The element to append to.
        ident: The ID to declare (default: the kind's key).
        description: Whether to write the kind's ``<description>``.
    """
    element = ("Condition" if kind.key in CONDITION_KINDS else KIND_ELEMENTS[kind.category])
    model = ET.SubElement(parent, element, {"ID": ident or kind.key})
    for attr in kind.settings():
        if attr.port is not None:
            port = attr.port
            default = None if port.default is NO_DEFAULT else port.default
            model_port(model, port.name, cpp_type(port.type), default, port.description,
                       element=PORT_ELEMENTS[port.direction.value])
            continue
        default = None if attr.required or attr.default == "" else attr.default
        model_port(model, attr.name, KIND_CPP_TYPES[attr.type], default, attr.description)
    if description and kind.description:
        text = f"{kind.description} {kind.differences}" if kind.differences else kind.description
        ET.SubElement(model, "description").text = text


def palette_text(registry: Registry) -> str:
    """Return the palette of every node kind as BT.CPP 4 XML, sorted by ID.

    Args:
        registry: The plugins, leaves and the controls and decorators they add (beside the
            engine's kinds).
    """
    root = ET.Element("root", {"BTCPP_format": "4"})
    models = ET.SubElement(root, "TreeNodesModel")
    makers = {plugin.name: lambda p=plugin: leaf_model(p, models) for plugin in registry}
    for kind in (*CONTROL_KINDS, *SCRIPT_KINDS, *(k.kind for k in registry.kind_plugins())):
        makers[kind.key] = lambda k=kind: kind_model(k, models)
    for kind in (k for k in PY_TREES_KINDS.values() if not always_builtin(k)):
        makers[custom_id(kind)] = lambda k=kind: kind_model(k, models, ident=custom_id(k))
    for ident in sorted(makers):
        makers[ident]()
    ET.indent(root, space="  ")
    header = ('<?xml version="1.0" encoding="UTF-8"?>\n'
              "<!-- Generated by 'sar-tree palette' from the node kinds and the registered "
              "leaf plugins. -->\n")
    return header + ET.tostring(root, "unicode") + "\n"
