"""A tree's ``blackboard:`` section in BehaviorTree.CPP 4 XML, both ways.

BT.CPP 4.7.3 has no place in a file for a blackboard's initial state (a program sets it
in C++), so the export writes it as two parts:

* **The initial values, for BT.CPP to run.** The ``<BehaviorTree>`` of a scope with
  initial values holds ``<Sequence name="InitialBlackboard">`` whose first child is
  ``<RunOnce name="InitialBlackboard" then_skip="true">`` around
  ``<Script name="InitialBlackboard" code="battery := 60.0; scans := 0"/>`` and whose
  second child is the tree's own root. ``RunOnce`` runs the script on the first tick of
  that tree instance only (then it is SKIPPED, which a ``Sequence`` passes over), as our
  loader writes initial values once, when the tree is built; ``:=`` creates the entry in
  the scope's blackboard, with the literal's type (``0`` int, ``60.0`` double, ``'a'``
  string, ``true`` bool; a list is written ``'a;b'``, as BT.CPP reads a vector port).
* **The declarations, for a re-import.** ``<Blackboard ID="TREE">`` under ``<root>`` lists
  each declared entry as ``<Entry name="battery" type="float">description</Entry>`` (our
  type names); BT.CPP's parser reads only ``<BehaviorTree>``, ``<TreeNodesModel>`` and
  ``<include>`` under ``<root>`` and ignores it. An entry without an assignment in the
  script has no initial value: the caller sets it.

The import recognises that exact shape (:func:`unwrap_initial`), folds the script back
into ``blackboard:`` (typed by ``<Blackboard>`` where it says, else by the literal) and
drops the wrapper; any other ``Script`` stays an ordinary node.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from collections.abc import Mapping
from typing import Any

from sar_framework.engine.message_literals import MessageLiteral, message_text
from sar_framework.engine.ports import NO_DEFAULT
from sar_framework.engine.spec import Declared
from sar_framework.interop.btcpp_models import convert_literal
from sar_framework.interop.xml_source import Element

#: The name of the three nodes that set a scope's initial values.
INIT_NAME = "InitialBlackboard"
#: The element under ``<root>`` that declares one tree's entries.
DECLARATIONS_TAG = "Blackboard"
_LITERAL = r"'[^']*'|\"[^\"]*\"|true|false|-?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?"
_ASSIGNMENT = re.compile(rf"\s*([A-Za-z_]\w*)\s*:=\s*({_LITERAL})\s*(?:;|$)")


def script_literal(value: Any) -> str:
    """``value`` as a literal of BT.CPP's script language.

    Raises:
        ValueError: A text holding both quote characters (the language has no escapes).
    """
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, MessageLiteral):  # as BT.CPP's convertFromString reads it back
        text = message_text(value)
    elif isinstance(value, (list, tuple)):
        text = ";".join(str(v) for v in value)
    else:
        text = str(value)
    if "'" not in text:
        return f"'{text}'"
    if '"' not in text:
        return f'"{text}"'
    raise ValueError(f"the initial value {text!r} holds both ' and \": BT.CPP's script "
                     "language cannot write it")


def initial_code(declared: Mapping[str, Declared]) -> str:
    """The script assigning every declared initial value (empty when there is none).

    Raises:
        ValueError: ``file:line:col: error: ...`` at a value the script cannot write.
    """
    parts = []
    for name, decl in declared.items():
        if decl.initial is NO_DEFAULT:
            continue
        try:
            parts.append(f"{name} := {script_literal(decl.initial)}")
        except ValueError as exc:
            raise ValueError(f"{decl.where}: error: '{name}': {exc}") from None
    return "; ".join(parts)


def with_initial(root: ET.Element, declared: Mapping[str, Declared]) -> ET.Element:
    """``root`` preceded by the run-once script of the initial values, if there are any."""
    code = initial_code(declared)
    if not code:
        return root
    sequence = ET.Element("Sequence", {"name": INIT_NAME})
    once = ET.SubElement(sequence, "RunOnce", {"name": INIT_NAME, "then_skip": "true"})
    ET.SubElement(once, "Script", {"name": INIT_NAME, "code": code})
    sequence.append(root)
    return sequence


def declarations_element(tree: str, declared: Mapping[str, Declared]) -> ET.Element | None:
    """The ``<Blackboard ID=tree>`` element of a scope's declarations (None: no section)."""
    if not declared:
        return None
    element = ET.Element(DECLARATIONS_TAG, {"ID": tree})
    for name, decl in declared.items():
        ET.SubElement(element, "Entry", {"name": name, "type": decl.type}).text = \
            decl.description or None
    return element


def parse_initial(code: str) -> dict[str, Any] | None:
    """The ``name := literal; ...`` assignments of ``code`` (None when it is anything else)."""
    values: dict[str, Any] = {}
    at = 0
    while at < len(code.rstrip()):
        match = _ASSIGNMENT.match(code, at)
        if match is None or match.end() == at:
            return None
        name, text = match.groups()
        if text[0] in "'\"":
            values[name] = text[1:-1]
        elif text in ("true", "false"):
            values[name] = text == "true"
        else:
            values[name] = float(text) if re.search(r"[.eE]", text) else int(text)
        at = match.end()
    return values or None


def unwrap_initial(element: Element) -> tuple[Element, dict[str, Any]] | None:
    """Split the exported initial-value wrapper off a tree's root element.

    Returns:
        The tree's own root and the initial values, or None when ``element`` is not the
        exact shape :func:`with_initial` writes.
    """
    if element.tag != "Sequence" or element.attrs != {"name": INIT_NAME} \
            or len(element.children) != 2:
        return None
    once = element.children[0]
    if once.tag != "RunOnce" or once.attrs != {"name": INIT_NAME, "then_skip": "true"} \
            or len(once.children) != 1:
        return None
    script = once.children[0]
    if script.tag != "Script" or script.children or set(script.attrs) != {"name", "code"} \
            or script.attrs["name"] != INIT_NAME:
        return None
    values = parse_initial(script.attrs["code"])
    return None if values is None else (element.children[1], values)


def read_declarations(element: Element) -> dict[str, dict[str, Any]]:
    """A ``<Blackboard>`` element's entries: name -> ``{type[, description]}``."""
    out: dict[str, dict[str, Any]] = {}
    for entry in element.children:
        name = entry.attrs.get("name")
        if entry.tag != "Entry" or not name:
            continue
        out[name] = {"type": entry.attrs.get("type", "any")}
        text = (entry.text or "").strip()
        if text:
            out[name]["description"] = text
    return out


def merged_section(declared: dict[str, dict[str, Any]] | None,
                   initial: dict[str, Any]) -> dict[str, dict[str, Any]]:
    """A ``blackboard:`` section from the declarations and the initial values.

    Args:
        declared: ``<Blackboard>``'s entries, or the ones the importer inferred.
        initial: The initial-value script's assignments.

    Returns:
        Name -> ``{type, initial, description}``, the declarations' order first; an
        initial value is converted to the declared type (a list from ``a;b``).
    """
    section = {name: dict(decl) for name, decl in (declared or {}).items()}
    for name, written in initial.items():
        decl = section.setdefault(name, {"type": _literal_type(written)})
        decl["initial"] = _typed(written, decl.get("type", "any"))
    return {name: _ordered(decl) for name, decl in section.items()}


def _typed(value: Any, kind: str) -> Any:
    if isinstance(value, str) and kind == "list":
        return [part for part in value.split(";") if part]
    if isinstance(value, str):
        return convert_literal(value, kind)
    return float(value) if kind == "float" and isinstance(value, int) else value


def _literal_type(value: Any) -> str:
    return {bool: "bool", int: "int", float: "float"}.get(type(value), "str")


def _ordered(decl: dict[str, Any]) -> dict[str, Any]:
    keys = ("type", "initial", "description")
    return {k: decl[k] for k in keys if k in decl} | {k: v for k, v in decl.items()
                                                        if k not in keys}


def scope_section(declared: Element | None,
                  initial: dict[str, Any] | None) -> dict[str, dict[str, Any]] | None:
    """The ``blackboard:`` section our export wrote for one tree, else None.

    Args:
        declared: The tree's ``<Blackboard>`` element, if the file has one.
        initial: The values its initial-value wrapper sets, if it has one.
    """
    if declared is None and initial is None:
        return None
    return merged_section(read_declarations(declared) if declared is not None else None,
                          initial or {})


def with_private(definition: Any, body: Any, section: dict[str, dict[str, Any]]) -> Any:
    """A subtree definition with ``section`` as its ``blackboard:``.

    Args:
        definition: The definition so far: its root ``body``, or the long form.
        body: The subtree's root node.
        section: Its declarations.

    Returns:
        The long form ``{ports, blackboard, root}``.
    """
    if definition is body:
        return {"blackboard": section, "root": body}
    definition.pop("blackboard", None)
    root = definition.pop("root")
    definition.update(blackboard=section, root=root)
    return definition
