"""The fields of ROS message types, read from the installed ``.msg`` files as text.

The engine imports no ROS: a type's definition is the text of
``share/<package>/msg/<Name>.msg`` under ``$AMENT_PREFIX_PATH`` or this Python's prefix
(where the ROS wheels install it), parsed by ``rosbags``' ``.msg`` parser. A literal for a
message is a mapping of its own fields (nested messages as nested mappings);
:func:`literal_problems` says what in one does not fit, with a did-you-mean::

    message_fields("geometry_msgs/msg/PoseStamped")
    # {'header': 'std_msgs/msg/Header', 'pose': 'geometry_msgs/msg/Pose'}
    literal_problems("geometry_msgs/msg/Pose", {"position": {"x": 1.0, "z": "up"}})
    # ["position.z: expected a float64, got 'up'"]
"""

from __future__ import annotations

import os
import sys
from functools import cache
from pathlib import Path
from typing import Any

from sar_framework.engine.diagnostics import did_you_mean

_INTS = frozenset({"byte", "char", "int8", "uint8", "int16", "uint16", "int32", "uint32",
                   "int64", "uint64"})
_FLOATS = frozenset({"float32", "float64"})


class MessageNotFoundError(LookupError):
    """No installed ``.msg`` file defines the type."""


def _msg_file(type_name: str) -> Path:
    package, _, name = type_name.partition("/msg/")
    prefixes = [p for p in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p]
    for prefix in dict.fromkeys([*prefixes, sys.prefix]):
        path = Path(prefix) / "share" / package / "msg" / f"{name}.msg"
        if path.is_file():
            return path
    raise MessageNotFoundError(f"no installed .msg file defines {type_name} (looked in "
                          "share/<package>/msg/ under $AMENT_PREFIX_PATH and this Python)")


def _type_text(spec: tuple[Any, Any]) -> str:
    """A field's type as text: ``float64``, ``geometry_msgs/msg/Point``, ``float64[]``."""
    kind, detail = spec
    if kind.name == "BASE":
        return str(detail[0])
    if kind.name == "NAME":
        return str(detail)
    inner, _size = detail
    return f"{_type_text(inner)}[]"


@cache
def message_fields(type_name: str) -> dict[str, str]:
    """The fields of ``pkg/msg/Name``: field name -> its type, in definition order.

    Raises:
        MessageNotFoundError: The type's ``.msg`` file is not installed.
    """
    from rosbags.typesys import get_types_from_msg  # only when a message is looked at

    types = get_types_from_msg(_msg_file(type_name).read_text(encoding="utf-8"), type_name)
    _constants, fields = types[type_name]
    return {name: _type_text(spec) for name, spec in fields}


def _scalar_problem(type_: str, value: Any) -> str | None:
    if type_ == "bool":
        ok = isinstance(value, bool)
    elif type_ in _INTS:
        ok = isinstance(value, int) and not isinstance(value, bool)
    elif type_ in _FLOATS:
        ok = isinstance(value, (int, float)) and not isinstance(value, bool)
    else:  # string, wstring
        ok = isinstance(value, str)
    return None if ok else f"expected a {type_}, got {value!r}"


#: A place in a literal: field names and list indices from its top.
LiteralPath = tuple[str | int, ...]
#: The type of a header's stamp, which also takes ``now`` (as ``ros2 topic pub`` does).
TIME = "builtin_interfaces/msg/Time"


def dotted(path: LiteralPath) -> str:
    """A literal path as text: ``pose.position.x``, ``poses[1].pose``."""
    out = ""
    for part in path:
        out += f"[{part}]" if isinstance(part, int) else f".{part}" if out else str(part)
    return out


def literal_problems(type_name: str, value: Any, at: str = "") -> list[str]:
    """What in a literal of ``type_name`` does not fit its fields (empty when it fits).

    Fields left out keep the message's defaults; each problem starts with the dotted path
    of the field (``pose.position.z: ...``).

    Raises:
        MessageNotFoundError: A type's ``.msg`` file is not installed.
    """
    prefix = f"{at}: " if at else ""
    return [f"{dotted(path)}: {text}" if path else f"{prefix}{text}"
            for path, text, _key in located_problems(type_name, value, (at,) if at else ())]


def located_problems(
    type_name: str, value: Any, at: LiteralPath = ()
) -> list[tuple[LiteralPath, str, bool]]:
    """:func:`literal_problems` with each problem's path kept apart, to locate it in a file.

    Returns:
        ``(path, text, at_key)`` per problem: ``at_key`` when the field's name is wrong
        (point at the key), else its value is.
    """
    if not isinstance(value, dict):
        return [(at, f"a {type_name} is written as a mapping of its fields "
                     f"({', '.join(message_fields(type_name))}), got {value!r}", False)]
    fields = message_fields(type_name)
    problems: list[tuple[LiteralPath, str, bool]] = []
    for name, given in value.items():
        path = (*at, str(name))
        type_ = fields.get(str(name))
        if type_ is None:
            problems.append((path, f"not a field of {type_name}{did_you_mean(str(name), fields)}"
                                   f" (fields: {', '.join(fields)})", True))
        elif type_.endswith("[]"):
            if not isinstance(given, list):
                problems.append((path, f"expected a list of {type_[:-2]}, got {given!r}", False))
            else:
                for index, item in enumerate(given):
                    problems += _field_problems(type_[:-2], item, (*path, index))
        else:
            problems += _field_problems(type_, given, path)
    return problems


def _field_problems(
    type_: str, value: Any, path: LiteralPath
) -> list[tuple[LiteralPath, str, bool]]:
    if type_ == TIME and value == "now":
        return []
    if "/" in type_:
        return located_problems(type_, value, path)
    problem = _scalar_problem(type_, value)
    return [(path, problem, False)] if problem else []
