"""Structure: a tree file's plain values, checked by ``jsonschema`` against the generated schema.

Each error of the Draft 2020-12 validator over :func:`.schema.tree_schema` maps back to
``file:line:col`` through the YAML nodes a :class:`.document.Document` remembers.
:class:`StructureCheck` words those errors for a user: the node kind and attribute they
concern, what was expected, what was found, and a "did you mean" where one is close; a
node without a name is named by its place in the file (:func:`node_label`).
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import jsonschema

from sar_framework.engine.checking.schema import tree_schema
from sar_framework.engine.diagnostics import Diagnostic, SourceLocation, did_you_mean
from sar_framework.engine.nodes.node_kinds import (
    KINDS,
    SUBTREE,
    TOP_LEVEL,
    UNSUPPORTED_DECORATORS,
    NodeKind,
    Rule,
)
from sar_framework.engine.ports import BASIC_TYPES, Port, entry_ref
from sar_framework.engine.reading.document import DocPath, Document, describe
from sar_framework.engine.registry import Registry

_TYPE_WORDS = {
    "string": "a string",
    "integer": "an integer",
    "number": "a number",
    "boolean": "a boolean (true or false)",
    "object": "a mapping",
}


def number(value: float) -> str:
    """Print a bound or a value the way it was most likely written (``1`` not ``1.0``)."""
    return str(int(value)) if isinstance(value, float) and value.is_integer() else str(value)


def suggest(word: str, names: list[str]) -> str:
    """Return a "did you mean", or the valid names when none is close (``_skipIf``... unlisted)."""
    listed = [name for name in names if not name.startswith("_")]
    return did_you_mean(word, names) or f" (expected one of: {', '.join(listed)})"


#: What an unknown plugin name with nothing close to it is told: the two routes to a leaf.
UNKNOWN_PLUGIN_HINT = (
    " (if it is a leaf of your own: install its package (an entry point in group "
    "'sar_framework.plugins'), or name its module, .py file or folder in the tree's "
    "'plugins:' key or with --plugin-path; see docs/tutorials/02_writing_a_plugin.md)")


def node_label(kind: str, path: DocPath, value: Any) -> str:
    """Name the node at ``path`` (its attributes) for a message.

    ``sequence 'Patrol'`` when it has a name; otherwise where it is: ``the root sequence``,
    ``sequence (child 2 of selector 'Mission')``, ``sequence (the child of timeout)``.

    Args:
        kind: The node's kind.
        path: The path of its attribute mapping in the document.
        value: The document's value.
    """
    def at(where: DocPath) -> Any:
        node = value
        for key in where:
            try:
                node = node[key]
            except (KeyError, IndexError, TypeError):
                return None
        return node

    attrs = at(path)
    if isinstance(attrs, dict) and isinstance(attrs.get("name"), str):
        return f"{kind} '{attrs['name']}'"
    above = path[:-1]  # the node's own mapping {kind: attrs}
    if above and above[-1] == "root":
        return f"the root {kind}"
    if len(above) >= 3 and isinstance(above[-1], int) and above[-2] == "children":
        parent = node_label(str(above[-3]), above[:-2], value)
        return f"{kind} (child {above[-1] + 1} of {parent})"
    if len(above) >= 2 and above[-1] == "child":
        return f"{kind} (the child of {node_label(str(above[-2]), above[:-1], value)})"
    return kind


#: Schemas and validators by the registry's plugins (their specs live as long as their classes).
_SCHEMAS: dict[tuple[tuple[str, int], ...], tuple[dict[str, Any], Any, tuple[Any, ...]]] = {}
#: How many registries' schemas are kept (tests make many small registries).
_SCHEMAS_KEPT = 8


class StructureCheck:
    """The schema check of one registry's tree format.

    Args:
        registry: The plugins whose params the schema holds.
    """

    def __init__(self, registry: Registry) -> None:
        self.registry = registry
        # The schema of the same plugins is the same: built once (it was half of a validate).
        plugins = tuple(registry)
        key = tuple((plugin.name, id(plugin)) for plugin in plugins)
        if key not in _SCHEMAS:
            if len(_SCHEMAS) >= _SCHEMAS_KEPT:
                _SCHEMAS.pop(next(iter(_SCHEMAS)))
            schema = tree_schema(registry)
            # The plugins are kept with it, so no id in the key is reused while it is kept.
            _SCHEMAS[key] = (schema, jsonschema.Draft202012Validator(schema), plugins)
        self.schema, self.validator, _ = _SCHEMAS[key]
        self.node_schema = self.schema["$defs"]["node"]

    def check(self, doc: Document) -> list[Diagnostic]:
        """Return every structural problem of ``doc``, worded, with its location.

        Args:
            doc: A converted file.

        Returns:
            The diagnostics (none when the file follows the schema).
        """
        if doc.too_deep is not None:
            return []
        errors = list(self.validator.iter_errors(doc.value))
        # A node with several keys is reported once, as such; nothing below it.
        crowded = [tuple(e.absolute_path) for e in errors if e.validator == "maxProperties"]
        out = []
        for error in errors:
            path: DocPath = tuple(error.absolute_path)
            if any(path[: len(p)] == p for p in doc.reported):
                continue
            if any(path[: len(c)] == c and error.validator != "maxProperties" for c in crowded):
                continue
            out.extend(Diagnostic(where, message) for where, message in self.word(error, doc))
        return out

    # -- wording ------------------------------------------------------------------------
    def word(
        self, error: jsonschema.ValidationError, doc: Document
    ) -> Iterator[tuple[SourceLocation, str]]:
        """Yield ``(where, message)`` for one jsonschema error."""
        path: DocPath = tuple(error.absolute_path)
        kind = error.validator
        instance = error.instance
        owner = self.owner(path)
        attr = str(path[-1]) if path else ""
        if kind == "additionalProperties":
            for key in instance:
                if key not in error.schema.get("properties", {}):
                    yield doc.key_where((*path, key)), self.unknown_key(path, key, error.schema)
        elif kind == "required" and len(path) >= 2 and path[-2] == "blackboard":
            yield doc.key_where(path), (f"entry '{path[-1]}' needs a 'type' (one of "
                                        f"{', '.join(BASIC_TYPES)}, or pkg/msg/Type)")
        elif kind == "required":
            rule = self.rule(error, owner)
            for name in error.validator_value:
                if name not in instance:
                    yield self.owner_where(path, doc), self.missing(owner, name, instance, rule)
        elif kind == "not" and "required" in error.validator_value:
            name = error.validator_value["required"][0]
            rule = self.rule(error, owner)
            yield doc.key_where((*path, name)), f"'{name}' is not allowed {rule}"
        elif kind == "not":
            yield doc.where(path), f"'{attr}' must not be {number(instance)}"
        elif kind == "type":
            yield doc.where(path), self.wrong_type(error, path, doc)
        elif kind == "enum":
            choices = [c for c in error.validator_value if c is not None]
            hint = did_you_mean(instance, map(str, choices)) if isinstance(instance, str) else ""
            yield doc.where(path), (f"'{attr}' must be one of: {', '.join(map(str, choices))}; "
                                    f"got {describe(instance)}{hint}")
        elif kind in ("minimum", "maximum", "exclusiveMinimum"):
            sign = {"minimum": ">=", "maximum": "<=", "exclusiveMinimum": ">"}[kind]
            yield doc.where(path), (f"'{attr}' must be {sign} {number(error.validator_value)}, "
                                    f"got {number(instance)}")
        elif kind == "minItems" and attr == "children" and error.validator_value == 1:
            yield doc.where(path), (f"{node_label(owner, path[:-1], doc.value)} has no children "
                                    "(a composite needs at least one)")
        elif kind == "pattern" and "propertyNames" in error.schema_path:
            yield doc.key_where((*path, instance)), (
                f"'{instance}' is not a valid entry name (letters, digits and '_', "
                "not starting with a digit)")
        elif kind in ("minItems", "maxItems") and attr == "children":
            bound = "at least" if kind == "minItems" else "at most"
            yield doc.where(path), (f"{owner} takes {bound} {error.validator_value} children, "
                                    f"got {len(instance)}")
        elif kind == "minLength" and "propertyNames" in error.schema_path:
            yield doc.key_where((*path, instance)), "a subtree name must not be empty"
        elif kind == "minLength" and attr == SUBTREE:
            yield doc.where(path), f"'subtree' must name a subtree, got {describe(instance)}"
        elif kind in ("minItems", "minLength"):
            yield doc.where(path), f"'{attr}' must not be empty"
        elif kind == "maxProperties":
            keys = list(instance)
            first = keys[0]
            known = self.attr_names(first)
            hint = (f" (indent the attributes under '{first}')"
                    if known and all(k in known for k in keys[1:]) else "")
            shown = ", ".join(f"'{k}'" for k in keys)
            yield doc.key_where((*path, keys[1])), (f"a node has exactly one key, its kind; "
                                                    f"got {shown}{hint}")
        elif kind == "minProperties":
            yield doc.where(path), "empty node: expected one key naming the node kind"
        else:  # a schema keyword this wording does not know yet: jsonschema's own words
            yield doc.where(path), error.message

    def kind(self, key: object) -> NodeKind | None:
        """The declaration of a node kind, built in or a plugin's, or None."""
        if not isinstance(key, str):
            return None
        return KINDS.get(key) or self.registry.kind(key)

    def owner(self, path: DocPath) -> str:
        """Return the node kind whose attributes hold ``path`` (the nearest above it)."""
        for index in range(len(path) - 1, -1, -1):
            key = path[index]
            if isinstance(key, str) and (self.kind(key) or key == SUBTREE or key in self.registry):
                return key
        return ""

    def owner_where(self, path: DocPath, doc: Document) -> SourceLocation:
        """Where to report a missing attribute: the node's key, or the file's start."""
        return doc.key_where(path) if path else doc.where(path)

    def attr_names(self, key: str) -> list[str] | None:
        """The attribute names of a node kind or plugin, in schema order, or None."""
        if key == SUBTREE:
            return list(self.schema["$defs"]["subtree.use"]["else"]["properties"])
        prefix = "kind" if self.kind(key) else "plugin"
        schema = self.schema["$defs"].get(f"{prefix}.{key}")
        return list(schema["properties"]) if schema is not None else None

    def rule(self, error: jsonschema.ValidationError, owner: str) -> str:
        """Word the condition of a rule (``when policy is X``), or "" for a plain error."""
        schema_path = list(error.schema_path)
        kind = self.kind(owner)
        if "allOf" not in schema_path or kind is None:
            return ""
        found: Rule = kind.rules[schema_path[schema_path.index("allOf") + 1]]
        word = "when" if "then" in schema_path else "unless"
        return f"{word} {found.if_attr} is {found.equals}"

    def unknown_key(self, path: DocPath, key: str, error_schema: dict[str, Any]) -> str:
        """Word a key the schema does not allow: top-level key, node kind or attribute."""
        if not path:
            return f"unknown top-level key '{key}'" + suggest(key, list(TOP_LEVEL))
        if error_schema is self.node_schema:
            if key in UNSUPPORTED_DECORATORS:
                return f"decorator '{key}' is not supported: {UNSUPPORTED_DECORATORS[key]}"
            candidates = [*KINDS, SUBTREE, *self.registry.names(),
                          *(k.name for k in self.registry.kind_plugins())]
            return f"unknown plugin '{key}'" + (did_you_mean(key, candidates)
                                                 or UNKNOWN_PLUGIN_HINT)
        owner = str(path[-1])
        names = self.attr_names(owner) or list(error_schema.get("properties", {}))
        if len(path) == 2 and path[0] == "subtrees":
            return f"unknown key '{key}' in subtree definition '{owner}'" + suggest(key, names)
        if len(path) >= 2 and path[-2] in ("blackboard", "ports"):
            return f"unknown key '{key}' for '{owner}'" + suggest(key, names)
        if owner in self.registry:
            plugin = self.registry.get(owner)
            moved = dict(plugin.moved) if plugin is not None else {}
            if key in moved:
                return f"unknown param '{key}' for plugin '{owner}': {moved[key]}"
            what = "param or port" if plugin is not None and plugin.ports else "param"
            return f"unknown {what} '{key}' for plugin '{owner}'" + suggest(key, names)
        what = f"unknown attribute '{key}' for {owner}"
        kind = self.kind(owner)
        category = kind.category.value if kind is not None else ""
        if key == "children" and category == "decorator":
            return f"{what} (a decorator has exactly one 'child')"
        if key == "child" and category == "composite":
            return f"{what} (a composite has a list of 'children')"
        return what + suggest(key, names)

    def missing(self, owner: str, name: str, instance: dict[str, Any], rule: str) -> str:
        """Word a missing required attribute of ``owner`` (the top level when empty)."""
        if not owner:
            return "missing 'format: 1' (the tree format version)"
        if rule:
            return f"{owner} needs '{name}' {rule}"
        label = f"{owner} '{instance['name']}'" if isinstance(instance.get("name"), str) else owner
        if name == "memory":
            return (f"{label} needs 'memory: true' (resume at the running child) or "
                    "'memory: false' (start again from the first child every tick)")
        if name == "child":
            return f"{label} needs a 'child' (a decorator has exactly one)"
        if name == "children":
            return f"{label} needs 'children' (a composite has at least one)"
        plugin = self.registry.get(owner)
        noun = "attribute" if plugin is None else "port" if plugin.port(name) else "param"
        return f"{label} is missing required {noun} '{name}'"

    def wrong_type(self, error: jsonschema.ValidationError, path: DocPath, doc: Document) -> str:
        """Word a value of the wrong type, by where it stands."""
        instance = error.instance
        got = describe(instance, doc.nodes.get(path))
        if error.schema is self.node_schema:
            hint = ""
            if isinstance(instance, str) and (self.kind(instance) or instance in self.registry):
                hint = f" (write '{instance}: {{}}')"
            return ("expected a node: a one-key mapping such as 'NavigateToPose: {}', "
                    f"got {got}{hint}")
        attr = str(path[-1]) if path else ""
        port = self.port_of(path)
        if port is not None:
            return self.wrong_port_value(attr, error, instance, got, port)
        if attr == "subtrees":
            return f"'subtrees' must be a mapping of names to nodes, got {got}"
        if attr == SUBTREE:
            return f"'subtree' must name a subtree, got {got}"
        if len(path) >= 2 and path[-2] in ("blackboard", "ports") and "properties" in error.schema:
            return f"'{attr}' must be a mapping such as {{type: int}}, got {got}"
        if "properties" in error.schema:  # the attributes of a node kind
            hint = f" (write '{attr}: {{}}')" if instance is None else ""
            return f"the attributes of '{attr}' must be a mapping, got {got}{hint}"
        if isinstance(path[-1], int):
            return f"items of '{path[-2]}' must be strings, got {got}"
        expected = error.validator_value
        expected = expected[0] if isinstance(expected, list) else expected
        if expected == "array":
            items = error.schema.get("items", {})
            word = "a list of nodes" if "$ref" in items else "a list of strings"
        else:
            word = _TYPE_WORDS.get(expected, expected)
        hint = ""
        if isinstance(instance, str) and entry_ref(instance) is not None:
            hint = " (a param, not a port: it cannot be bound to a blackboard entry)"
        return f"'{attr}' must be {word}, got {got}{hint}"

    def port_of(self, path: DocPath) -> Port | None:
        """Return the leaf port whose binding stands at ``path``, or None."""
        if len(path) < 2 or not isinstance(path[-1], str) or not isinstance(path[-2], str):
            return None
        plugin = self.registry.get(path[-2])
        return plugin.port(path[-1]) if plugin is not None else None

    def wrong_port_value(
        self, attr: str, error: jsonschema.ValidationError, instance: Any, got: str,
        port: Port,
    ) -> str:
        """Word a port binding of the wrong type (an unquoted ``{key}`` above all)."""
        expected = error.validator_value
        if expected == "string":
            word = "an entry ('{key}')"
        else:
            words = [_TYPE_WORDS.get(t, "a list" if t == "array" else t)
                     for t in expected if t != "string"]
            if port.type in ("str", "any"):  # text is a literal too, not only an entry
                words.insert(0, "a string")
            listed = ", ".join(words[:-1]) + " or " if len(words) > 1 else ""
            word = f"{listed}{words[-1]} literal, or an entry ('{{key}}')"
        hint = ""
        if isinstance(instance, dict) and len(instance) == 1 and None in instance.values():
            (name,) = instance
            hint = f" (quote it: '\"{{{name}}}\"'; unquoted, YAML reads {{{name}}} as a mapping)"
        return f"port '{attr}' must be bound to {word}, got {got}{hint}"
