"""What a drawn node says (kind symbol, settings, params, ports) and its data edges.

:func:`data_edges` links a node writing an entry to the nodes reading it. Shared by the
Graphviz diagram (:mod:`.render`) and the terminal tree (:mod:`.text_tree`).
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from typing import Any

from sar_framework.engine.ports import NO_DEFAULT, entry_ref
from sar_framework.engine.spec import Category, NodeSpec, TreeSpec

MAX_VALUE_CHARS = 40
CONTROL_CHARS = re.compile(r"[\x00-\x1f\x7f]")
CONVERTER = re.compile(r"(success|failure|running)_is_(success|failure|running)")


@dataclass(frozen=True)
class Glyphs:
    """Characters that differ between the ASCII and the Unicode renderings."""

    arrow: str
    ellipsis: str
    tee: str
    corner: str
    pipe: str
    subtree_open: str
    subtree_close: str


UNICODE = Glyphs("→", "…", "├── ", "└── ", "│   ", "«", "»")
ASCII = Glyphs("->", "...", "|-- ", "`-- ", "|   ", "<<", ">>")


def clean(text: str) -> str:
    """Make ``text`` one printable line (control characters become spaces)."""
    text = CONTROL_CHARS.sub(" ", text)
    return text.encode("utf-8", "replace").decode("utf-8")


def format_value(value: Any, glyphs: Glyphs) -> str:
    """Format a param or attribute value compactly, YAML-like."""
    if isinstance(value, bool):
        text = "true" if value else "false"
    elif value is None:
        text = "null"
    elif isinstance(value, (int, float)):
        text = repr(value)
    else:
        text = json.dumps(value, ensure_ascii=False, default=str)
    if len(text) > MAX_VALUE_CHARS:
        text = text[: MAX_VALUE_CHARS - len(glyphs.ellipsis)] + glyphs.ellipsis
    return text


def symbol(node: NodeSpec) -> str:
    """Return py_trees' text symbol for the node's kind (and memory flag)."""
    if node.category is Category.LEAF:
        return "-->"
    if node.category is Category.DECORATOR:
        return "-^-"
    if node.symbol:  # the kind's declaration gives it
        return node.symbol
    if node.kind == "parallel":
        return "/_/"
    bar = "o" if node.kind == "selector" else "-"
    return f"{{{bar}}}" if node.attrs.get("memory", False) else f"[{bar}]"


def settings(node: NodeSpec, glyphs: Glyphs) -> list[str]:
    """Describe a composite's or decorator's settings as short phrases.

    Known kinds get a dedicated wording (``memory``/``reactive``, ``on_completion``,
    ``FAILURE -> SUCCESS``...); attributes not covered are listed as ``key=value``.
    """
    attrs = dict(node.attrs)
    out: list[str] = []
    if node.kind in ("sequence", "selector") and "memory" in attrs:
        out.append("memory" if attrs.pop("memory") else "reactive")
    elif node.kind == "parallel":
        if "policy" in attrs:
            out.append(str(attrs.pop("policy")))
        selected = attrs.pop("selected", None)
        if selected:
            out.append(f"selected={format_value(selected, glyphs)}")
        if attrs.pop("synchronise", False):
            out.append("synchronise")
        else:
            attrs.pop("synchronise", None)
    elif node.kind == "one_shot" and "policy" in attrs:
        out.append(str(attrs.pop("policy")))
    elif node.kind == "timeout" and isinstance(attrs.get("duration"), (int, float)):
        out.append(f"duration={format_value(attrs.pop('duration'), glyphs)}s")
    elif match := CONVERTER.fullmatch(node.kind):
        out.append(f"{match.group(1).upper()} {glyphs.arrow} {match.group(2).upper()}")
    out.extend(f"{key}={format_value(value, glyphs)}" for key, value in attrs.items())
    return [*out, *conditions(node, glyphs)]


def conditions(node: NodeSpec, glyphs: Glyphs) -> list[str]:
    """Describe the node's pre/post-conditions (``_skipIf="n > 9"``), as written."""
    return [f"{key}={format_value(script.text, glyphs)}"
            for key, script in node.scripts.items() if key.startswith("_")]


def leaf_params(node: NodeSpec, glyphs: Glyphs, all_params: bool) -> list[str]:
    """Describe a leaf's params and ports: ``key=value``, references as ``key -> id``.

    Only the params and ports the tree sets, unless ``all_params`` (then defaults too);
    params whose value is ``None`` (an unset optional) are left out. A port bound to an
    entry shows the binding as written (``goal={goal}``), a literal port its value.
    """
    out: list[str] = []
    for key, value in node.attrs.items():
        if not all_params and key not in node.written:
            continue
        if key in node.refs:
            target = node.refs[key].id or value
            out.append(f"{key} {glyphs.arrow} {target}")
        elif value is not None:
            out.append(f"{key}={format_value(value, glyphs)}")
    for key, value in port_settings(node, all_params).items():
        shown = value if entry_ref(value) is not None else format_value(value, glyphs)
        out.append(f"{key}={clean(shown)}")
    return [*out, *conditions(node, glyphs)]


def port_settings(node: NodeSpec, all_params: bool) -> dict[str, Any]:
    """The leaf's ports as written in the file, then (``all_params``) the declared defaults."""
    shown = dict(node.ports)
    if all_params:
        for key, binding in node.bindings.items():
            if key not in shown and binding.port.default is not NO_DEFAULT:
                shown[key] = binding.port.default
    return shown


def info_and_params(node: NodeSpec, glyphs: Glyphs, all_params: bool, *, id_sep: str,
                    kind: str) -> tuple[list[str], list[str]]:
    """What a drawing shows beside a node's name: its info, then its leaf params.

    Args:
        node: The node.
        glyphs: The characters to draw with.
        all_params: Show every leaf param, defaults included (default: only those set).
        id_sep: Between ``id`` and a leaf's id (``": "``, ``"="``).
        kind: How a control's kind is shown (its settings follow).

    Returns:
        A leaf's plugin (when it differs from its name) and id, or a control's kind and
        settings; then the leaf's params (none for a control).
    """
    if node.category is not Category.LEAF:
        return [kind, *settings(node, glyphs)], []
    info = [node.kind] if node.kind != node.name else []
    if node.id is not None:
        info.append(f"id{id_sep}{node.id}")
    return info, leaf_params(node, glyphs, all_params)


def insertion_ports(node: NodeSpec, glyphs: Glyphs) -> list[str]:
    """A subtree use's port values as written (``goal={goal}``, ``shelf=nw``), on its top node.

    Args:
        node: Any node; only the top node of an inserted subtree has ports.
        glyphs: The ellipsis of a long value.

    Returns:
        One ``name=value`` per port the use sets, in the file's order.
    """
    ports = node.insertion.get("ports") if node.subtree is not None else None
    if not isinstance(ports, dict):
        return []
    return [f"{name}={value if isinstance(value, str) else format_value(value, glyphs)}"
            for name, value in ports.items()]


def data_edges(spec: TreeSpec) -> list[tuple[str, str, str]]:
    """Return ``(writer uid, reader uid, entry)`` for every entry a node writes and one reads.

    A node's ports and its scripts both count.

    Args:
        spec: The validated tree.

    Returns:
        One edge per writer, reader and entry (a node reading its own write is left out).
    """
    writers: dict[str, list[str]] = {}
    readers: dict[str, list[str]] = {}
    for node in spec.nodes():
        reads: set[str] = set()
        writes: set[str] = set()
        for binding in node.bindings.values():
            if binding.key is not None and binding.port.direction.writes:
                writes.add(binding.key)
            if binding.key is not None and binding.port.direction.reads:
                reads.add(binding.key)
        for script in node.scripts.values():
            writes.update(node.script_keys[n] for n in script.writes if node.script_keys.get(n))
            reads.update(node.script_keys[n] for n in script.reads if node.script_keys.get(n))
        for key in sorted(writes):
            writers.setdefault(key, []).append(node.uid)
        for key in sorted(reads):
            readers.setdefault(key, []).append(node.uid)
    return [(w, r, key[1:]) for key, ws in writers.items() for w in ws
            for r in readers.get(key, ()) if r != w]
