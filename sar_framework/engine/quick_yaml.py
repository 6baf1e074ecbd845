"""A reader for the plain subset of YAML that tree files are written in, or nothing.

Composing a big tree with libyaml costs more than validating and building it: every
scalar, mapping and list becomes a :class:`yaml.nodes.Node` with two marks. Tree files
use a small corner of YAML, one construct per line::

    root:                                   # key, block value below
      sequence:
        name: Patrol                        # key: plain scalar
        memory: true
        children:
          - NavigateToZone: {}              # list item holding a key: flow mapping
          - retry: {num_failures: 3, child: {Tick: {}}}
          - Log: {name: 'Done?', text: "a b"}

:func:`parse` reads exactly that corner and returns plain values (``dict``, ``list``,
``str``, ``int``, ``float``, ``bool``, None), where every mapping that is the value of a
key comes as ``(mapping, line, col)`` with the 1-based position of that key: the only
positions a valid tree needs (a node's location is its kind's key). Anything else
returns None, and the caller falls back to PyYAML, which stays the reference: anchors,
tags, multi-line or escaped scalars, block scalars, tabs, non-ASCII text, carriage
returns, duplicate or non-string keys, a key with an empty value, lists indented level
with their key, several documents, ... Plain scalars are resolved by PyYAML's own
resolver and constructors, so ``yes``, ``0x1F``, ``1_000`` or ``.inf`` mean what they
mean to PyYAML.

When :func:`parse` returns a value, it equals ``yaml.safe_load`` of the same text once
each ``(mapping, line, col)`` is replaced by ``mapping``, and each such position is
where PyYAML's composer places the key. ``tests/engine/test_quick_yaml.py`` checks
this on the repository's trees and on generated and mutated documents.
"""

from __future__ import annotations

import re
from typing import Any

from yaml.nodes import ScalarNode

from sar_framework.engine import yaml_source

#: A mapping; a mapping that is the value of a key is held as ``(mapping, line, col)``.
Mapping = dict[str, Any]

# Printable ASCII and line feeds only: tabs, CR, control and non-ASCII characters each
# have rules of their own in YAML, so a text holding one goes to PyYAML.
_SUBSET_BYTES = bytes(range(32, 127)) + b"\n"

_KEY = r"[A-Za-z_][A-Za-z0-9_]{0,127}"  # identifiers only (PyYAML caps simple keys)
# Every line of the text, one match each (MULTILINE): the indent, then either content
# (an optional "- ", then "key:" with an optional value after spaces, or a value
# alone) without trailing spaces, or anything else (blank lines included). Greedy, so
# matching is linear; a comment is cut off the value in Python.
_LINES = re.compile(
    r"^( *)(?:(- +)?(?:(" + _KEY + r"):(?:( +)([^\n]*[^ \n]))?|([^ \n](?:[^\n]*[^ \n])?)) *"
    r"|([^\n]*))$",
    re.MULTILINE,
)

# Plain scalars: a first character that cannot start anything else in YAML, then no
# character that could end the scalar or start a comment or mapping value.
_PLAIN_FIRST = r"(?:[A-Za-z0-9_.~/+]|-(?=[0-9.]))"
_PLAIN_BLOCK = re.compile(_PLAIN_FIRST + r"[^#:]*")
_PLAIN_FLOW = _PLAIN_FIRST + r"[^,\[\]{}#: ]*(?: +[^,\[\]{}#: ]+)*"
_SINGLE = r"'((?:[^']|'')*)'"
_DOUBLE = r'"([^"\\]*)"'
_SINGLE_QUOTED = re.compile(_SINGLE)
_DOUBLE_QUOTED = re.compile(_DOUBLE)

# A flow mapping whose values are all scalars (the usual leaf), read in one go.
_FLOW_SCALAR = rf"(?:{_SINGLE}|{_DOUBLE}|({_PLAIN_FLOW}))"
_FLAT_ENTRY = rf"{_KEY}: +(?:'(?:[^']|'')*'|\"[^\"\\]*\"|{_PLAIN_FLOW})"
_FLAT_MAPPING = re.compile(rf"\{{ *{_FLAT_ENTRY}(?: *, *{_FLAT_ENTRY})* *\}}")
_FLAT_PAIR = re.compile(rf"({_KEY}): +{_FLOW_SCALAR}")

# Flow tokens, each after optional spaces: punctuation, a key (identifier + ": "), a
# quoted scalar or a plain scalar.
_FLOW_TOKEN = re.compile(
    rf" *(?:(?P<punct>[{{}}\[\],])|(?P<key>{_KEY}): |{_SINGLE}|{_DOUBLE}|({_PLAIN_FLOW}))"
)
_MAX_FLOW_DEPTH = 64

_STR_TAG = yaml_source.STR_TAG
_PLAIN = (True, False)  # the "implicit" flags PyYAML's resolver gets for a plain scalar
_resolve = yaml_source.resolve_tag
# Timestamps and binary values are outside the subset (no tree attribute takes one).
_BUILDERS = {
    tag: build
    for tag, build in yaml_source.SCALAR_BUILDERS.items()
    if tag.endswith(("null", "bool", "int", "float"))
}
# Memos of plain scalars and keys seen (bounded: a long-lived process reads many files).
_MEMO_SIZE = 65536
_plain_memo: dict[str, Any] = {}
_good_keys: set[str] = set()


class _OutsideError(Exception):
    """The text leaves the subset (internal: :func:`parse` returns None)."""


def _plain(text: str) -> Any:
    """The value of a plain scalar, as PyYAML's safe loader reads it."""
    try:
        return _plain_memo[text]
    except KeyError:
        pass
    tag = _resolve(ScalarNode, text, _PLAIN)
    if tag == _STR_TAG:
        value: Any = text
    else:
        builder = _BUILDERS.get(tag)
        if builder is None:
            raise _OutsideError
        try:
            value = builder(ScalarNode(tag, text))
        except Exception as exc:  # a value PyYAML would also refuse
            raise _OutsideError from exc
    if len(_plain_memo) < _MEMO_SIZE:
        _plain_memo[text] = value
    return value


def _key(text: str) -> str:
    """Check that a key is a string to PyYAML (not ``true``, ``null``, ``on``, ...)."""
    if text not in _good_keys:
        if _resolve(ScalarNode, text, _PLAIN) != _STR_TAG:
            raise _OutsideError
        if len(_good_keys) < _MEMO_SIZE:
            _good_keys.add(text)
    return text


def _value(text: str, line: int, col: int) -> Any:
    """The value written on one line after ``key:`` or ``-``; ``col``: where it starts."""
    first = text[0]
    if first == "{":
        if text == "{}":
            return {}
        if _FLAT_MAPPING.fullmatch(text) is not None:
            mapping: Mapping = {}
            for key, single, double, plain in _FLAT_PAIR.findall(text):
                if key in mapping:
                    raise _OutsideError
                # findall gives "" for an unmatched group: an empty plain scalar is
                # impossible, so "" there means a quoted scalar.
                mapping[_key(key)] = (
                    _plain(plain) if plain else double if single == "" else
                    single.replace("''", "'")
                )
            return mapping
    if first in ("{", "["):
        return _flow(text, line, col)
    if first == "'":
        match = _SINGLE_QUOTED.fullmatch(text)
        if match is None:
            raise _OutsideError
        return match.group(1).replace("''", "'")
    if first == '"':
        match = _DOUBLE_QUOTED.fullmatch(text)
        if match is None:
            raise _OutsideError
        return match.group(1)
    if _PLAIN_BLOCK.fullmatch(text) is None:
        raise _OutsideError
    return _plain(text)


def _flow(text: str, line: int, col: int) -> Any:
    """Read a whole flow value (``{...}`` or ``[...]``) written at ``col`` of ``line``."""
    value, end = _flow_at(text, 0, line, col, 0)
    if end != len(text):
        raise _OutsideError  # something after the value
    return value


def _flow_at(text: str, pos: int, line: int, col: int, depth: int) -> tuple[Any, int]:
    """Read one flow value of ``text`` at ``pos``; return it and the position after it."""
    if depth > _MAX_FLOW_DEPTH:
        raise _OutsideError
    if text.startswith("{}", pos):  # the usual value of a leaf without params
        return {}, pos + 2
    match = _FLOW_TOKEN.match(text, pos)
    if match is None:
        raise _OutsideError
    punct, _, single, double, plain = match.groups()
    end = match.end()
    if punct is None:
        if plain is not None:
            return _plain(plain), end
        if single is not None:
            return single.replace("''", "'"), end
        if double is not None:
            return double, end
        raise _OutsideError  # a key where a value belongs
    if punct == "{":
        mapping: Mapping = {}
        while True:
            match = _FLOW_TOKEN.match(text, end)
            if match is None:
                raise _OutsideError
            punct, key = match.group("punct", "key")
            if punct == "}" and not mapping:
                return mapping, match.end()
            if key is None or key in mapping:
                raise _OutsideError
            key_col = col + match.start("key")
            value, end = _flow_at(text, match.end(), line, col, depth + 1)
            mapping[_key(key)] = (value, line, key_col) if type(value) is dict else value
            match = _FLOW_TOKEN.match(text, end)
            if match is None:
                raise _OutsideError
            punct = match.group("punct")
            end = match.end()
            if punct == "}":
                return mapping, end
            if punct != ",":
                raise _OutsideError
    if punct == "[":
        items: list[Any] = []
        match = _FLOW_TOKEN.match(text, end)
        if match is not None and match.group("punct") == "]":
            return items, match.end()
        while True:
            value, end = _flow_at(text, end, line, col, depth + 1)
            items.append(value)
            match = _FLOW_TOKEN.match(text, end)
            if match is None:
                raise _OutsideError
            punct = match.group("punct")
            end = match.end()
            if punct == "]":
                return items, end
            if punct != ",":
                raise _OutsideError
    raise _OutsideError  # "}", "]" or "," where a value belongs


def _uncomment(value: str) -> str:
    """Cut a comment (``#`` first, or after a space) off a value.

    A ``#`` inside a quoted scalar is cut too: what is left is then not a valid scalar,
    and the text goes to PyYAML.
    """
    if value[0] == "#":
        return ""
    at = value.find(" #")
    return value if at < 0 else value[:at].rstrip(" ")


def parse(text: str) -> Mapping | None:
    """Read a tree file's text if it stays inside the subset.

    Args:
        text: The decoded file (without a byte-order mark).

    Returns:
        The top-level mapping (each mapping-valued key as ``(mapping, line, col)``);
        None when the text uses anything outside the subset (ask PyYAML instead).
    """
    if not text.isascii() or not yaml_source.PURE_RESOLUTION:
        return None
    if text.encode("ascii").translate(None, _SUBSET_BYTES):
        return None  # a control character
    try:
        return _parse_lines(text)
    except _OutsideError:
        return None


def _parse_lines(text: str) -> Mapping:
    root: Mapping = {}
    # Open block collections, innermost last: (column of their entries, collection).
    stack: list[tuple[int, Any]] = []
    top_col = -1  # the innermost collection's column (-1 before the first line)
    top: Any = None
    # A key written with no value on its line: (its mapping, its column, key, line, col).
    pending: tuple[Mapping, int, str, int, int] | None = None
    for number, (indent_text, dash, key, space, written, written_item, other) in enumerate(
        _LINES.findall(text), 1
    ):
        value, item = written, written_item
        if key:
            if value and "#" in value:
                value = _uncomment(value)
        elif item:
            if "#" in item:
                if item[0] == "#" and not dash:
                    continue  # a comment line
                item = _uncomment(item)
                if not item:
                    raise _OutsideError
            if not dash:
                raise _OutsideError
        elif other.strip(" "):
            raise _OutsideError
        else:
            continue  # a blank line
        indent = len(indent_text)
        if pending is not None:
            # The pending key's value is the collection this line starts: deeper, or a
            # list level with its key ("indentless", as PyYAML's dumper writes lists).
            mapping, map_col, pending_key, key_line, key_col = pending
            if indent < map_col or (indent == map_col and not dash):
                raise _OutsideError  # an empty value
            top = [] if dash else {}
            mapping[pending_key] = (top, key_line, key_col) if not dash else top
            top_col = indent
            stack.append((indent, top))
            pending = None
        elif top_col != indent:
            if top_col < 0:
                if indent or dash:
                    raise _OutsideError  # a document is one mapping, at column 0
                top, top_col = root, 0
                stack.append((0, root))
            else:
                while top_col > indent:
                    stack.pop()
                    top_col, top = stack[-1]  # the root (column 0) is never popped
                if top_col != indent:
                    raise _OutsideError
        if dash:
            if type(top) is not list:
                raise _OutsideError
            content_col = indent + len(dash)
            if not key:
                top.append({} if item == "{}" else _value(item, number, content_col + 1))
                continue
            if key not in _good_keys:
                _key(key)
            if value:
                # A one-line item (`- Kind: {...}`): its mapping is complete, so it is not
                # opened; a second key for it on the next line then leaves the subset.
                if value == "{}":
                    parsed: Any = {}
                else:
                    parsed = _value(value, number, content_col + len(key) + len(space) + 2)
                top.append({key: (parsed, number, content_col + 1)
                            if type(parsed) is dict else parsed})
                continue
            mapping = {}
            top.append(mapping)
            top, top_col = mapping, content_col
            stack.append((content_col, mapping))
        else:
            if type(top) is list and len(stack) > 1 and stack[-2][0] == top_col:
                stack.pop()  # the end of a list level with its key: back to the mapping
                top_col, top = stack[-1]
            if type(top) is not dict or not key:
                raise _OutsideError
            mapping = top
        if key in mapping:
            raise _OutsideError  # a duplicate key: PyYAML keeps the last, we report it
        if key not in _good_keys:
            _key(key)
        if not value:
            pending = (mapping, top_col, key, number, top_col + 1)
        elif value == "{}":
            mapping[key] = ({}, number, top_col + 1)
        else:
            value_col = top_col + len(key) + len(space) + 2
            parsed = _value(value, number, value_col)
            mapping[key] = (parsed, number, top_col + 1) if type(parsed) is dict else parsed
    if pending is not None or top_col < 0:
        raise _OutsideError  # a key with an empty value at the end, or no content at all
    return root
