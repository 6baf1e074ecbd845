"""The JSON Schema (Draft 2020-12) of the tree format, generated from the declarations.

The schema is built from the same tables the validator walks: the top-level
keys (:data:`.node_kinds.TOP_LEVEL_ATTRS`), the composite/decorator kinds
(:mod:`.node_kinds`) and every registered plugin's params. Editors use it
through yaml-language-server (``# yaml-language-server: $schema=...``) to
complete and check tree files; a test keeps the committed copy
(``sar_framework/schema/tree.schema.json``) in step with the code.

A node is an object with exactly one property, the node kind; each kind's
value schema lives in ``$defs`` (``kind.sequence``, ``plugin.NavigateToPose``).
"""

from __future__ import annotations

import json
from collections.abc import Iterable
from typing import Any

from sar_framework.engine.message_literals import MessageLiteral
from sar_framework.engine.nodes.kind_model import CONDITION_ATTRS
from sar_framework.engine.nodes.node_kinds import (
    FORMAT_VERSION,
    KINDS,
    SUBTREE,
    TOP_LEVEL_ATTRS,
    Attr,
    AttrType,
    NodeKind,
    leaf_attrs,
)
from sar_framework.engine.ports import (
    BASIC_TYPES,
    ENTRY_NAME,
    NO_DEFAULT,
    Direction,
    Naming,
    Port,
    is_message,
)
from sar_framework.engine.registry import Registry

DRAFT = "https://json-schema.org/draft/2020-12/schema"
SCHEMA_ID = "https://github.com/sar-framework/sar_framework/schema/tree.schema.json"
_NODE_REF = {"$ref": "#/$defs/node"}
#: The JSON types of a literal each basic input port type accepts (a string may be an
#: entry); a message type's input takes a mapping (its fields, or a pose shorthand) or a
#: string (an entry or a text form); every output a string only.
PORT_JSON_TYPES: dict[str, list[str]] = {
    "str": ["string", "number", "boolean"],
    "int": ["integer", "string"],
    "float": ["number", "string"],
    "bool": ["boolean", "string"],
    "list": ["array", "string"],
    "any": ["string", "number", "boolean", "array"],
}
_MESSAGE_JSON_TYPES = ["string", "object"]
_MESSAGE_LITERAL = ("A literal: the message's fields as a mapping; a pose also "
                    "{x, y, yaw} or 'x;y;yaw'.")
_BINDING = "Bind an entry with '{key}' (this scope), '{@key}' (the root) or '{=}'."
_ENTRY_NAMES = {"type": "string", "pattern": ENTRY_NAME.pattern}
_TYPE_NAME = {
    "type": "string",
    "description": f"A port type: {', '.join(BASIC_TYPES)} or a ROS message pkg/msg/Type.",
    "examples": [*BASIC_TYPES, "geometry_msgs/msg/PoseStamped"],
}


_JSON_TYPES: dict[str, tuple[type, ...]] = {
    "string": (str,), "integer": (int,), "number": (int, float), "boolean": (bool,),
    "array": (list,), "object": (dict,),
}  # fmt: skip


def fits_port(port: Port, value: Any) -> bool:
    """Whether the schema lets ``value`` bind ``port`` (so other checks do not repeat it)."""
    allowed = ["string"]
    if port.direction is Direction.INPUT and port.naming is Naming.VALUE:
        allowed = _literal_types(port.type) or allowed
    for name in allowed:
        if isinstance(value, bool) and name != "boolean":
            continue
        if isinstance(value, _JSON_TYPES[name]):
            return True
        if name == "integer" and isinstance(value, float) and value.is_integer():
            return True
    return False


def port_schema(port: Port) -> dict[str, Any]:
    """Return the JSON Schema of a leaf port's binding, with the hover text editors show.

    Args:
        port: The port declaration.

    Returns:
        The schema fragment: the literal types it takes (inputs), or a string (an entry).
    """
    head = f"{port.direction.value} port ({port.type})"
    text = f"{head}: {port.description}" if port.description else head
    if port.naming is not Naming.VALUE:
        return {"description": text, "type": "string", "minLength": 1}
    if port.direction is Direction.INPUT and is_message(port.type):
        text += f" {_MESSAGE_LITERAL}"
    out: dict[str, Any] = {"description": f"{text} {_BINDING}"}
    literal = _literal_types(port.type) if port.direction is Direction.INPUT else None
    out["type"] = literal or "string"
    if isinstance(port.default, MessageLiteral):
        out["default"] = port.default.fields
    elif port.default is not NO_DEFAULT:
        out["default"] = port.default
    return out


def _literal_types(type_: str) -> list[str] | None:
    """The JSON types of an input port's literal (None: a string only)."""
    return _MESSAGE_JSON_TYPES if is_message(type_) else PORT_JSON_TYPES.get(type_)


def _declarations(what: str, props: dict[str, Any], required: list[str]) -> dict[str, Any]:
    entry: dict[str, Any] = {"type": "object", "properties": props,
                             "additionalProperties": False}
    if required:
        entry["required"] = required
    return {"description": what, "type": "object", "propertyNames": _ENTRY_NAMES,
            "additionalProperties": entry}


#: ``blackboard:`` (top level, or in a subtree definition): entry -> declaration.
BLACKBOARD_SCHEMA = _declarations(
    "Blackboard entries: name -> {type, initial, description}. An entry without "
    "'initial' is an input the caller sets.",
    {"type": _TYPE_NAME, "initial": {"description": "Written before the first tick."},
     "description": {"type": "string"}},
    ["type"],
)
#: ``ports:`` of a subtree definition: port name -> declaration.
SUBTREE_PORTS_SCHEMA = _declarations(
    "The subtree's ports: name -> {direction, type, default, description}.",
    {"direction": {"enum": [d.value for d in Direction], "default": "input"},
     "type": _TYPE_NAME, "default": {"description": "A literal, used when not remapped."},
     "description": {"type": "string"}},
    [],
)
#: The long form of a subtree definition.
SUBTREE_DEFINITION = {
    "type": "object",
    "description": "A subtree with declared ports (the short form is just its root node).",
    "properties": {"description": {"type": "string"}, "ports": SUBTREE_PORTS_SCHEMA,
                   "blackboard": BLACKBOARD_SCHEMA, "root": _NODE_REF},
    "required": ["root"],
    "additionalProperties": False,
}
#: ``subtree:`` as a node: a name, or the long form with remapped ports.
SUBTREE_USE = {
    "description": "Insert a fresh copy of the named subtree: 'subtree: NAME' or "
    "'subtree: {tree: NAME, ports: {inner: \"{outer}\" | literal}, autoremap: true}', "
    "with pre/post-conditions ('_skipIf'...) as a BT.CPP SubTree takes them.",
    "if": {"type": "string"},
    "then": {"minLength": 1},
    "else": {
        "type": "object",
        "properties": {
            "tree": {"type": "string", "minLength": 1, "description": "The subtree's name."},
            "ports": {"type": "object", "propertyNames": _ENTRY_NAMES,
                      "description": "Subtree port -> '{outer entry}' or a literal."},
            "autoremap": {"type": "boolean", "default": False,
                          "description": "Entries not remapped use the parent's entry of "
                          "the same name (not those starting with '_')."},
            **{a.name: {"type": "string", "minLength": 1, "description": a.description
                        + " (evaluated in the parent's scope)"} for a in CONDITION_ATTRS},
        },
        "required": ["tree"],
        "additionalProperties": False,
    },
}


def attr_schema(attr: Attr) -> dict[str, Any]:
    """Return the JSON Schema of one attribute's value.

    Args:
        attr: The attribute.

    Returns:
        The schema fragment, with description and default for editors.
    """
    out: dict[str, Any] = {}
    if attr.description:
        out["description"] = attr.description
    kind = attr.type
    if kind is AttrType.PORT and attr.port is not None:
        out = port_schema(attr.port)
        if attr.minimum is not None:  # bounds a literal; '{name}' is a string
            out["minimum"] = attr.minimum
        return out
    if kind is AttrType.SCRIPT:
        out.update({"type": "string", "minLength": 1})
        return out
    if kind is AttrType.NODE:
        out.update(_NODE_REF)
        return out
    if kind is AttrType.NODES:
        out.update({"type": "array", "items": _NODE_REF})
        if attr.min_items is not None:
            out["minItems"] = attr.min_items
        if attr.max_items is not None:
            out["maxItems"] = attr.max_items
        return out
    if kind is AttrType.STRINGS:
        out.update({"type": "array", "items": {"type": "string"}})
        if attr.min_items is not None:
            out["minItems"] = attr.min_items
        return out
    out["type"] = [kind.value, "null"] if attr.nullable else kind.value
    if attr.enum is not None:
        out["enum"] = [*attr.enum, None] if attr.nullable else list(attr.enum)
    if attr.min_length is not None:
        out["minLength"] = attr.min_length
    if attr.minimum is not None:
        out["minimum"] = attr.minimum
    if attr.exclusive_minimum is not None:
        out["exclusiveMinimum"] = attr.exclusive_minimum
    if attr.maximum is not None:
        out["maximum"] = attr.maximum
    if attr.excluded:
        out["not"] = {"enum": list(attr.excluded)}
    if not attr.required and (attr.default is not None or attr.nullable):
        out["default"] = attr.default
    if attr.ref is not None:
        lead = f"id of a {attr.ref} leaf."
        out["description"] = f"{lead} {attr.description}" if attr.description else lead
    return out


def _object(
    attrs: Iterable[Attr], description: str, rules: Iterable[Any] = ()
) -> dict[str, Any]:
    attrs = tuple(attrs)
    out: dict[str, Any] = {"type": "object"}
    if description:
        out["description"] = description
    out["properties"] = {a.name: attr_schema(a) for a in attrs}
    required = [a.name for a in attrs if a.required]
    if required:
        out["required"] = required
    out["additionalProperties"] = False
    conditions = []
    for rule in rules:
        clause: dict[str, Any] = {
            "if": {"properties": {rule.if_attr: {"const": rule.equals}}, "required": [rule.if_attr]}
        }
        for branch, what in (("then", rule.then), ("else", rule.otherwise)):
            if what == "required":
                clause[branch] = {"required": [rule.attr]}
            elif what == "forbidden":
                clause[branch] = {"not": {"required": [rule.attr]}}
        conditions.append(clause)
    if conditions:
        out["allOf"] = conditions
    return out


def _kind_schema(kind: NodeKind) -> dict[str, Any]:
    word = {"composite": "Composite", "decorator": "Decorator"}.get(kind.category.value, "Leaf")
    return _object(kind.attrs, f"{word} {kind.class_name}: {kind.description}", kind.rules)


def tree_schema(registry: Registry) -> dict[str, Any]:
    """Build the full schema of a tree file.

    Args:
        registry: The plugins whose params the schema includes.

    Returns:
        The schema as a JSON-ready dict.
    """
    defs: dict[str, Any] = {}
    kinds: dict[str, Any] = {}
    for key, kind in (*KINDS.items(), *((k.name, k.kind) for k in registry.kind_plugins())):
        defs[f"kind.{key}"] = _kind_schema(kind)
        kinds[key] = {"$ref": f"#/$defs/kind.{key}"}
    kinds[SUBTREE] = {"$ref": "#/$defs/subtree.use"}
    defs["subtree.use"] = SUBTREE_USE
    defs["subtree.definition"] = SUBTREE_DEFINITION
    for plugin in registry:
        defs[f"plugin.{plugin.name}"] = _object(leaf_attrs(plugin), plugin.description)
        kinds[plugin.name] = {"$ref": f"#/$defs/plugin.{plugin.name}"}
    defs["node"] = {
        "description": "A node: one key, the node kind (composite, decorator, plugin or "
        "subtree), whose value holds its attributes.",
        "type": "object",
        "minProperties": 1,
        "maxProperties": 1,
        "properties": kinds,
        "additionalProperties": False,
    }
    top = _object(TOP_LEVEL_ATTRS, f"A sar_framework behaviour tree (format {FORMAT_VERSION}).")
    top["properties"]["subtrees"] = {
        "description": "Named fragments, inserted with {subtree: NAME}: NAME: NODE, or NAME: "
        "{ports, blackboard, root} to declare its ports.",
        "type": "object",
        "propertyNames": {"type": "string", "minLength": 1},
        "additionalProperties": {
            "if": {"type": "object", "required": ["root"]},
            "then": {"$ref": "#/$defs/subtree.definition"},
            "else": _NODE_REF,
        },
    }
    top["properties"]["blackboard"] = BLACKBOARD_SCHEMA
    return {"$schema": DRAFT, "$id": SCHEMA_ID, "title": "sar_framework tree", **top,
            "$defs": defs}  # fmt: skip


def schema_text(registry: Registry) -> str:
    """Return :func:`tree_schema` as the JSON text ``sar-tree schema`` prints."""
    return json.dumps(tree_schema(registry), indent=2, ensure_ascii=False) + "\n"
