"""The JSON Schema (Draft 2020-12) of the tree format, generated from the declarations.

The schema is built from the same tables the validator walks: the top-level
keys (:data:`.node_kinds.TOP_LEVEL_ATTRS`), the composite/decorator kinds
(:mod:`.node_kinds`) and every registered plugin's params. Editors use it
through yaml-language-server (``# yaml-language-server: $schema=...``) to
complete and check tree files; a test keeps the committed copy
(``sar_framework/schema/tree.schema.json``) in step with the code.

A node is an object with exactly one property, the node kind; each kind's
value schema lives in ``$defs`` (``kind.sequence``, ``plugin.NavigateToZone``).
"""

from __future__ import annotations

import json
from collections.abc import Iterable
from typing import Any

from sar_framework.engine.node_kinds import (
    FORMAT_VERSION,
    KINDS,
    SUBTREE,
    TOP_LEVEL_ATTRS,
    Attr,
    AttrType,
    NodeKind,
    leaf_attrs,
)
from sar_framework.engine.registry import Registry

DRAFT = "https://json-schema.org/draft/2020-12/schema"
SCHEMA_ID = "https://github.com/sar-framework/sar_framework/schema/tree.schema.json"
_NODE_REF = {"$ref": "#/$defs/node"}


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
    for key, kind in KINDS.items():
        defs[f"kind.{key}"] = _kind_schema(kind)
        kinds[key] = {"$ref": f"#/$defs/kind.{key}"}
    kinds[SUBTREE] = {
        "type": "string",
        "minLength": 1,
        "description": "Insert a fresh copy of the named subtree.",
    }
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
        "description": "Named fragments, inserted with {subtree: NAME}.",
        "type": "object",
        "propertyNames": {"type": "string", "minLength": 1},
        "additionalProperties": _NODE_REF,
    }
    return {"$schema": DRAFT, "$id": SCHEMA_ID, "title": "sar_framework tree", **top,
            "$defs": defs}  # fmt: skip


def schema_text(registry: Registry) -> str:
    """Return :func:`tree_schema` as the JSON text ``sar-tree schema`` prints."""
    return json.dumps(tree_schema(registry), indent=2, ensure_ascii=False) + "\n"
