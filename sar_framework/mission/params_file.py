"""Check a ROS 2 parameter file in pure Python before rcl reads it.

rcl's own YAML parser stops start-up with messages such as ``Couldn't parse params
file ... Error parsing a event near line 3, at /project/src/parse.c:782``, and an empty
list only fails later, when the node is created, with ``Cannot declare a statically
typed parameter with default value of type PARAMETER_NOT_SET``. This module reads the
file with PyYAML's safe composer (positions kept, nothing constructed) and reports the
first problem as ``file:line:col: key: problem``::

    try:
        keys = check_params_file("config/mission_params.yaml")
    except ParamsError as err:
        print(err)   # config/mission_params.yaml:3:17: zone_order: empty list (...)

It checks what rcl needs: a mapping of node names (optionally nested in namespaces)
down to ``ros__parameters``; under it, nested mappings of scalars or non-empty lists of
one scalar type; no null values, no duplicate keys. Nothing here imports ROS.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import yaml
from yaml.nodes import MappingNode, Node, ScalarNode, SequenceNode

_TAG = "tag:yaml.org,2002:"
_SCALAR_TYPES = {
    _TAG + "bool": "bool",
    _TAG + "int": "integer",
    _TAG + "float": "double",
    _TAG + "str": "string",
}
_NULL = _TAG + "null"
_PARAMS_KEY = "ros__parameters"


@dataclass(frozen=True)
class KeyLocation:
    """Where a parameter is set in a file.

    Attributes:
        file: The file, as the caller named it.
        line: 1-based line of the key.
        col: 1-based column of the key.
    """

    file: str
    line: int
    col: int


class ParamsError(ValueError):
    """A parameter file or a parameter value that start-up cannot use.

    The message is one line: ``file[:line[:col]]: key: problem``.

    Args:
        file: The parameter file (or a label such as ``mission parameters``).
        key: The dotted parameter name; empty when the problem is not about one key.
        problem: What is wrong, in words a user can act on.
        line: 1-based line, when known.
        col: 1-based column, when known.
    """

    def __init__(self, file: str, key: str, problem: str, line: int | None = None,
                 col: int | None = None) -> None:
        self.file = file
        self.key = key
        self.problem = problem
        self.line = line
        self.col = col
        where = file
        if line is not None:
            where += f":{line}" + (f":{col}" if col is not None else "")
        super().__init__(f"{where}: {key}: {problem}" if key else f"{where}: {problem}")


def params_files_from_args(args: Sequence[str]) -> list[str]:
    """Return the files named by ``--params-file`` inside ``--ros-args`` sections.

    Args:
        args: A command line (``sys.argv``).

    Returns:
        The parameter files in the order given (later files override earlier ones).
    """
    files: list[str] = []
    in_ros_args = False
    index = 0
    while index < len(args):
        arg = args[index]
        if arg == "--ros-args":
            in_ros_args = True
        elif arg == "--":
            in_ros_args = False
        elif in_ros_args and arg == "--params-file" and index + 1 < len(args):
            files.append(args[index + 1])
            index += 1
        index += 1
    return files


def _location(file: str, node: Node) -> tuple[int, int]:
    return node.start_mark.line + 1, node.start_mark.column + 1


def _fail(file: str, node: Node, key: str, problem: str) -> ParamsError:
    line, col = _location(file, node)
    return ParamsError(file, key, problem, line, col)


def _mapping_items(file: str, node: MappingNode, prefix: str) -> list[tuple[str, Node, Node]]:
    """Return ``(key, key_node, value_node)``; reject non-string and duplicate keys."""
    items: list[tuple[str, Node, Node]] = []
    seen: dict[str, int] = {}
    for key_node, value_node in node.value:
        if not isinstance(key_node, ScalarNode) or key_node.tag not in (
            _TAG + "str", _TAG + "int", _TAG + "bool", _TAG + "float"
        ):
            raise _fail(file, key_node, prefix.rstrip("."), "keys must be plain names")
        key = str(key_node.value)
        if key in seen:
            raise _fail(file, key_node, prefix + key,
                        f"duplicate key (first set on line {seen[key]})")
        seen[key] = key_node.start_mark.line + 1
        items.append((key, key_node, value_node))
    return items


def _check_value(file: str, key: str, node: Node) -> None:
    """Check one parameter value: a scalar or a non-empty list of one scalar type."""
    if isinstance(node, ScalarNode):
        if node.tag == _NULL:
            raise _fail(file, node, key, "no value (null); give a value or remove the key")
        if node.tag not in _SCALAR_TYPES:
            raise _fail(file, node, key, f"unsupported value type {node.tag!r}")
        return
    if isinstance(node, SequenceNode):
        if not node.value:
            raise _fail(file, node, key, "empty list (a ROS 2 parameter list needs at least "
                        "one value to have a type)")
        kinds: set[str] = set()
        for item in node.value:
            if not isinstance(item, ScalarNode) or item.tag not in _SCALAR_TYPES:
                raise _fail(file, item, key, "a list may only hold plain values "
                            "(bool, integer, double or string), not lists, maps or nulls")
            kinds.add(_SCALAR_TYPES[item.tag])
        if len(kinds) > 1:
            raise _fail(file, node, key, "a list must hold one type, got "
                        + " and ".join(sorted(kinds)) + " (quote strings, write 1.0 for doubles)")
        return
    raise _fail(file, node, key, "unsupported value")


def _check_parameters(file: str, node: Node, prefix: str,
                      keys: dict[str, KeyLocation]) -> None:
    """Walk the mapping under ``ros__parameters`` and record every leaf key."""
    if not isinstance(node, MappingNode):
        raise _fail(file, node, prefix.rstrip(".") or _PARAMS_KEY,
                    "expected a mapping of parameter names to values")
    for key, key_node, value_node in _mapping_items(file, node, prefix):
        name = prefix + key
        if isinstance(value_node, MappingNode):
            _check_parameters(file, value_node, name + ".", keys)
        else:
            _check_value(file, name, value_node)
            line, col = _location(file, key_node)
            keys[name] = KeyLocation(file, line, col)


def _check_section(file: str, node: Node, path: str, keys: dict[str, KeyLocation]) -> bool:
    """Walk node names / namespaces down to ``ros__parameters``; return whether one was found."""
    if not isinstance(node, MappingNode):
        raise _fail(file, node, path, f"expected a mapping holding '{_PARAMS_KEY}' "
                    "(a node name, or '/**' for every node)")
    found = False
    for key, _key_node, value_node in _mapping_items(file, node, path + "/" if path else ""):
        if key == _PARAMS_KEY:
            _check_parameters(file, value_node, "", keys)
            found = True
        else:
            found = _check_section(file, value_node, f"{path}/{key}" if path else key,
                                   keys) or found
    return found


def check_params_file(path: str | Path) -> dict[str, KeyLocation]:
    """Check a ROS 2 parameter file and return where each parameter is set.

    Args:
        path: The file, as the user named it (messages use it as given).

    Returns:
        Dotted parameter name (``zones.zone_a.x``) -> its location. When several node
        sections set a name, the last one wins (as for overrides).

    Raises:
        ParamsError: On the first problem found (unreadable file, YAML syntax, structure,
            value types), with file, line and column.
    """
    file = str(path)
    try:
        text = Path(path).read_text(encoding="utf-8")
    except FileNotFoundError:
        raise ParamsError(file, "", "file not found") from None
    except (OSError, UnicodeDecodeError) as err:
        raise ParamsError(file, "", f"cannot read the file: {err}") from None
    try:
        root = yaml.compose(text, Loader=yaml.SafeLoader)
    except yaml.MarkedYAMLError as err:
        mark = err.problem_mark or err.context_mark
        problem = ": ".join(str(p) for p in (err.context, err.problem) if p)
        line = mark.line + 1 if mark else None
        col = mark.column + 1 if mark else None
        raise ParamsError(file, "", f"YAML syntax error: {problem}", line, col) from None
    except yaml.YAMLError as err:
        raise ParamsError(file, "", f"YAML error: {err}") from None
    if root is None:
        raise ParamsError(file, "", f"empty file (expected '/**:' then '{_PARAMS_KEY}:')")
    keys: dict[str, KeyLocation] = {}
    if not _check_section(file, root, "", keys):
        raise ParamsError(file, "", f"no '{_PARAMS_KEY}' section (expected '/**:' then "
                          f"'  {_PARAMS_KEY}:')", 1, 1)
    return keys
