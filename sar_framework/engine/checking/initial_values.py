"""Initial values given from outside the file (``sar-tree run --set battery=50``).

A value overrides the initial value of an entry the main tree declares under
``blackboard:``. It is converted to the entry's declared type as a literal in the file
would be; a value that does not convert is an error at the declaration
(``tree.yaml:4:3: error: --set battery=full: expected a float, got 'full'``), a name the
tree does not declare an error at its ``blackboard:`` section (the file's start when it has
none) that names the command-line argument, with a did-you-mean.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable, Mapping
from typing import Any

import yaml

from sar_framework.engine.diagnostics import Diagnostic, SourceLocation, did_you_mean
from sar_framework.engine.ports import convert
from sar_framework.engine.spec import Entry, TreeSpec

#: How the option is named in messages.
OPTION = "--set"


class SetError(ValueError):
    """A ``NAME=VALUE`` text that is not one."""


def parse_settings(texts: Iterable[str]) -> dict[str, Any]:
    """``["battery=50", "name=nw"]`` -> ``{"battery": 50, "name": "nw"}``.

    A value is read as a YAML scalar or flow collection (``50`` an int, ``true`` a bool,
    ``[a, b]`` a list, ``'50'`` a string); an empty value is the empty string.

    Raises:
        SetError: A text without ``=`` or with an empty name, or a value YAML cannot read.
    """
    values: dict[str, Any] = {}
    for text in texts:
        name, equals, value = text.partition("=")
        if not equals or not name.strip():
            raise SetError(f"{OPTION} {text!r}: expected NAME=VALUE (e.g. battery=50)")
        try:
            values[name.strip()] = yaml.safe_load(value) if value.strip() else ""
        except yaml.YAMLError as exc:
            problem = getattr(exc, "problem", None) or "not a YAML value"
            raise SetError(f"{OPTION} {text!r}: {problem}") from None
    return values


def override_initial(spec: TreeSpec, values: Mapping[str, Any],
                     section: SourceLocation | None = None) -> list[Diagnostic]:
    """Make ``values`` the initial values of the main tree's declared entries.

    Args:
        spec: A validated tree; changed in place when there is no problem.
        values: Entry name -> value (as :func:`parse_settings` reads them).
        section: Where the main tree's ``blackboard:`` key is, if it has one.

    Returns:
        The problems (the spec is left as it was when there is any).
    """
    declared = spec.declarations.get("", {})
    problems: list[Diagnostic] = []
    converted: dict[str, Any] = {}
    for name, value in values.items():
        decl = declared.get(name)
        if decl is None:
            problems.append(_undeclared(spec, name, value, declared, section))
            continue
        try:
            converted[name] = convert(decl.type, value)
        except ValueError as exc:
            where = decl.where or SourceLocation(spec.source, 1, 1)
            problems.append(Diagnostic(where, f"{OPTION} {name}={value}: {exc} (the entry is "
                                              f"declared here as {decl.type})"))
    if problems:
        return problems
    for name, value in converted.items():
        declared[name] = dataclasses.replace(declared[name], initial=value)
        key = f"/{name}"
        entry = spec.entries.setdefault(key, Entry(key, declared[name].type))
        entry.initial = value
    return []


def _undeclared(spec: TreeSpec, name: str, value: Any, declared: Mapping[str, Any],
                section: SourceLocation | None) -> Diagnostic:
    """A name the main tree does not declare, given on the command line."""
    given = f"{OPTION} {name}={_shown(value)} (command-line argument)"
    hint = did_you_mean(name, declared)
    if section is None:
        return Diagnostic(SourceLocation(spec.source, 1, 1),
                          f"{given}: the tree declares no entry '{name}'{hint}: it has no "
                          "'blackboard:' section")
    names = ", ".join(declared) or "none"
    return Diagnostic(section, f"{given}: the tree declares no entry '{name}'{hint} in its "
                               f"'blackboard:' section (declared: {names})")


def _shown(value: Any) -> str:
    """A ``--set`` value as the command line gave it (YAML's text of it)."""
    if isinstance(value, str):
        return value
    return yaml.safe_dump(value, default_flow_style=True, width=1 << 16).strip().removesuffix(
        "\n...").strip()
