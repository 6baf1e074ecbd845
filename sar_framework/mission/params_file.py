"""Check a ROS 2 parameter file in pure Python before rcl reads it.

rcl's own YAML parser stops start-up with messages such as ``Couldn't parse params
file ... Error parsing a event near line 3, at /project/src/parse.c:782``, and an empty
list only fails later, when the node is created, with ``Cannot declare a statically
typed parameter with default value of type PARAMETER_NOT_SET``. This module reads the
file with PyYAML's safe composer (positions kept) and reports problems as
``file:line:col: key: problem``: :func:`read_params_file` returns every problem with the
values and where each key is set; :func:`check_params_file` raises the first::

    try:
        keys = check_params_file("config/mission_params.yaml")
    except ParamsError as err:
        print(err)   # config/mission_params.yaml:3:17: tick_rate_hz: must be > 0 (...)

It checks what rcl needs: a mapping of node names (optionally nested in namespaces)
down to ``ros__parameters``; under it, nested mappings of scalars or non-empty lists of
one scalar type; no null values, no duplicate keys. Nothing here imports ROS.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

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


@dataclass
class ParamsFile:
    """What a parameter file sets, and what is wrong with it.

    Attributes:
        file: The file, as the caller named it.
        values: Dotted parameter name -> its value (the last node section wins).
        locations: Dotted parameter name -> where it is set.
        problems: Every problem found, in file order.
    """

    file: str
    values: dict[str, Any] = field(default_factory=dict)
    locations: dict[str, KeyLocation] = field(default_factory=dict)
    problems: list[ParamsError] = field(default_factory=list)

    def add(self, node: Node, key: str, problem: str) -> None:
        """Record a problem at ``node``'s position."""
        self.problems.append(ParamsError(self.file, key, problem, node.start_mark.line + 1,
                                         node.start_mark.column + 1))

    # -- walking the YAML nodes ----------------------------------------------------------
    def mapping_items(self, node: MappingNode, prefix: str) -> list[tuple[str, Node, Node]]:
        """Return ``(key, key_node, value_node)``; skip non-string and duplicate keys."""
        items: list[tuple[str, Node, Node]] = []
        seen: dict[str, int] = {}
        for key_node, value_node in node.value:
            if not isinstance(key_node, ScalarNode) or key_node.tag not in (
                _TAG + "str", _TAG + "int", _TAG + "bool", _TAG + "float"
            ):
                self.add(key_node, prefix.rstrip("."), "keys must be plain names")
                continue
            key = str(key_node.value)
            if key in seen:
                self.add(key_node, prefix + key, f"duplicate key (first set on line {seen[key]})")
                continue
            seen[key] = key_node.start_mark.line + 1
            items.append((key, key_node, value_node))
        return items

    def value_problem(self, key: str, node: Node) -> bool:
        """Record the problem of one value, if any: a scalar or a non-empty list of one type."""
        before = len(self.problems)
        if isinstance(node, ScalarNode):
            if node.tag == _NULL:
                self.add(node, key, "no value (null); give a value or remove the key")
            elif node.tag not in _SCALAR_TYPES:
                self.add(node, key, f"unsupported value type {node.tag!r}")
        elif isinstance(node, SequenceNode):
            if not node.value:
                self.add(node, key, "empty list (a ROS 2 parameter list needs at least "
                         "one value to have a type)")
            kinds: set[str] = set()
            for item in node.value:
                if not isinstance(item, ScalarNode) or item.tag not in _SCALAR_TYPES:
                    self.add(item, key, "a list may only hold plain values "
                             "(bool, integer, double or string), not lists, maps or nulls")
                    return True
                kinds.add(_SCALAR_TYPES[item.tag])
            if len(kinds) > 1:
                self.add(node, key, "a list must hold one type, got " + " and ".join(
                    sorted(kinds)) + " (quote strings, write 1.0 for doubles)")
        else:
            self.add(node, key, "unsupported value")
        return len(self.problems) > before

    def parameters(self, node: Node, prefix: str) -> None:
        """Walk the mapping under ``ros__parameters`` and record every leaf key."""
        if not isinstance(node, MappingNode):
            self.add(node, prefix.rstrip(".") or _PARAMS_KEY,
                     "expected a mapping of parameter names to values")
            return
        for key, key_node, value_node in self.mapping_items(node, prefix):
            name = prefix + key
            if isinstance(value_node, MappingNode):
                self.parameters(value_node, name + ".")
            elif not self.value_problem(name, value_node):
                self.values[name] = yaml.SafeLoader("").construct_object(value_node, deep=True)
                self.locations[name] = KeyLocation(self.file, key_node.start_mark.line + 1,
                                                   key_node.start_mark.column + 1)

    def section(self, node: Node, path: str) -> bool:
        """Walk node names / namespaces down to ``ros__parameters``; return if one was found."""
        if not isinstance(node, MappingNode):
            self.add(node, path, f"expected a mapping holding '{_PARAMS_KEY}' "
                     "(a node name, or '/**' for every node)")
            return True  # reported: no second message about a missing section
        found = False
        for key, _key_node, value_node in self.mapping_items(node, path + "/" if path else ""):
            if key == _PARAMS_KEY:
                self.parameters(value_node, "")
                found = True
            else:
                found = self.section(value_node, f"{path}/{key}" if path else key) or found
        return found


def read_params_file(path: str | Path) -> ParamsFile:
    """Read a ROS 2 parameter file: its values, where each is set, and every problem.

    Args:
        path: The file, as the user named it (messages use it as given).

    Returns:
        The contents; ``problems`` is empty when rcl would accept the file.
    """
    contents = ParamsFile(str(path))
    file = contents.file
    try:
        text = Path(path).read_text(encoding="utf-8")
    except FileNotFoundError:
        contents.problems.append(ParamsError(file, "", "file not found"))
        return contents
    except (OSError, UnicodeDecodeError) as err:
        contents.problems.append(ParamsError(file, "", f"cannot read the file: {err}"))
        return contents
    try:
        root = yaml.compose(text, Loader=yaml.SafeLoader)
    except yaml.MarkedYAMLError as err:
        mark = err.problem_mark or err.context_mark
        problem = ": ".join(str(p) for p in (err.context, err.problem) if p)
        line = mark.line + 1 if mark else None
        col = mark.column + 1 if mark else None
        contents.problems.append(
            ParamsError(file, "", f"YAML syntax error: {problem}", line, col))
        return contents
    except yaml.YAMLError as err:
        contents.problems.append(ParamsError(file, "", f"YAML error: {err}"))
        return contents
    if root is None:
        contents.problems.append(
            ParamsError(file, "", f"empty file (expected '/**:' then '{_PARAMS_KEY}:')"))
    elif not contents.section(root, ""):
        contents.problems.append(ParamsError(file, "", f"no '{_PARAMS_KEY}' section (expected "
                                             f"'/**:' then '  {_PARAMS_KEY}:')", 1, 1))
    return contents


def check_params_file(path: str | Path) -> dict[str, KeyLocation]:
    """Check a ROS 2 parameter file and return where each parameter is set.

    Args:
        path: The file, as the user named it (messages use it as given).

    Returns:
        Dotted parameter name (``initial_pose.x``) -> its location. When several node
        sections set a name, the last one wins (as for overrides).

    Raises:
        ParamsError: On the first problem found (unreadable file, YAML syntax, structure,
            value types), with file, line and column.
    """
    contents = read_params_file(path)
    if contents.problems:
        raise contents.problems[0]
    return contents.locations
