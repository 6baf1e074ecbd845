"""Literals of message-typed ports: the message's own fields, a pose shorthand or Nav2's text.

A port of a ROS message type takes, besides an entry (``"{goal}"``), a literal written as

* the message's own fields, in YAML (nested messages as mappings, arrays as lists)::

    goal: {header: {frame_id: odom}, pose: {position: {x: 1.0, y: 2.0}}}

* for the pose types of :data:`POSE_AT`, the shorthand ``{x, y, yaw}`` (radians; ``z``
  and, for a stamped type, ``frame_id`` too)::

    goal: {x: 1.0, y: 2.0, yaw: 0.0}

* text, as BT.CPP's ``convertFromString`` reads it in XML: Nav2's forms (a ``Point``
  ``x;y;z``, a ``Quaternion`` ``x;y;z;w``, a ``PoseStamped``
  ``stamp_ns;frame;x;y;z;qx;qy;qz;qw``) and, for the pose types, ``x;y;yaw``.

Fields left out keep the message's defaults, except the top-level ``header`` of a stamped
message: its ``frame_id`` is ``map`` and its ``stamp`` is ``now`` (the node's clock when
the leaf reads the port, as ``ros2 topic pub`` reads ``now``) unless the literal gives
them. The engine keeps the result as a :class:`MessageLiteral`, plain data; the leaf
toolkit makes the message of it when a leaf reads the port.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from sar_framework.engine.diagnostics import did_you_mean
from sar_framework.engine.messages import (
    LiteralPath,
    MessageNotFoundError,
    dotted,
    located_problems,
    message_fields,
)

HEADER = "std_msgs/msg/Header"
#: Where the ``geometry_msgs/Pose`` lies in each type that takes the pose shorthand.
POSE_AT: dict[str, tuple[str, ...]] = {
    "geometry_msgs/msg/Pose": (),
    "geometry_msgs/msg/PoseStamped": ("pose",),
    "geometry_msgs/msg/PoseWithCovariance": ("pose",),
    "geometry_msgs/msg/PoseWithCovarianceStamped": ("pose", "pose"),
}
_PLANAR = "geometry_msgs/msg/Pose2D"  # its own fields are x, y, theta: yaw is theta
_SHORTHAND = ("x", "y", "z", "yaw")
#: Nav2's text forms (``bt_utils.hpp``): the type -> its fields, in the order written.
_NAV2_TEXT: dict[str, tuple[str, ...]] = {
    "geometry_msgs/msg/Point": ("x", "y", "z"),
    "geometry_msgs/msg/Quaternion": ("x", "y", "z", "w"),
    "geometry_msgs/msg/PoseStamped": ("stamp_ns", "frame_id", "x", "y", "z", "qx", "qy", "qz",
                                      "qw"),
}


class LiteralError(ValueError):
    """A literal that does not fit its message type.

    Attributes:
        problems: ``(path, text, at_key)`` per problem (see
            :func:`~.messages.located_problems`).
    """

    def __init__(self, problems: list[tuple[LiteralPath, str, bool]]) -> None:
        super().__init__("; ".join(f"{dotted(p)}: {t}" if p else t for p, t, _ in problems))
        self.problems = problems


@dataclass(frozen=True, eq=True)
class MessageLiteral:
    """A message written in a tree file, as plain data.

    Attributes:
        type: The message type, ``pkg/msg/Type``.
        fields: The fields it sets (nested mappings and lists; a stamp may be ``"now"``),
            in the form ``rosidl_runtime_py.set_message_fields`` takes.
    """

    type: str
    fields: dict[str, Any]

    def __str__(self) -> str:
        """Compact: a pose as ``PoseStamped(x=1, y=2, yaw=0)`` (``@frame`` unless ``map``)."""
        name = self.type.rpartition("/")[2]
        pose = _planar(self)
        if pose is None:
            return f"{name}{self.fields}"
        (x, y, yaw), frame = pose
        where = f"@{frame}" if frame not in (None, "map") else ""
        return f"{name}{where}(x={x:g}, y={y:g}, yaw={yaw:.3g})"


def _planar(literal: MessageLiteral) -> tuple[tuple[float, float, float], Any] | None:
    """A pose literal's ``(x, y, yaw)`` and frame (None for another type)."""
    if literal.type == _PLANAR:
        f = literal.fields
        return (f.get("x", 0.0), f.get("y", 0.0), f.get("theta", 0.0)), None
    if literal.type not in POSE_AT:
        return None
    pose: Any = literal.fields
    for name in POSE_AT[literal.type]:
        pose = pose.get(name, {})
    position, q = pose.get("position", {}), pose.get("orientation", {})
    qx, qy, qz, qw = (q.get(k, 1.0 if k == "w" else 0.0) for k in "xyzw")
    yaw = math.atan2(2 * (qw * qz + qx * qy), 1 - 2 * (qy * qy + qz * qz))
    frame = literal.fields.get("header", {}).get("frame_id")
    return (position.get("x", 0.0), position.get("y", 0.0), yaw), frame


def message_literal(type_: str, value: Any) -> MessageLiteral:
    """Read a literal of a message type (fields, pose shorthand or text).

    Args:
        type_: The message type, ``pkg/msg/Type``.
        value: The literal as the tree file gives it.

    Returns:
        The literal, with the header's frame and stamp filled.

    Raises:
        LiteralError: With each problem's path, when it does not fit or the type's ``.msg``
            file is not installed.
    """
    try:
        return _literal(type_, value)
    except MessageNotFoundError as exc:
        raise LiteralError([((), str(exc), False)]) from None


def _literal(type_: str, value: Any) -> MessageLiteral:
    if isinstance(value, dict) and len(value) == 1 and None in value.values():
        (name,) = value
        raise LiteralError([((), f"got a mapping {{{name}: null}}: to bind the entry, quote it: "
                                 f"'\"{{{name}}}\"' (unquoted, YAML reads {{{name}}} as a "
                                 "mapping)", False)])
    if isinstance(value, str):
        fields = _from_text(type_, value)
    elif isinstance(value, dict) and _is_shorthand(type_, value):
        fields = _from_shorthand(type_, value)
    else:
        problems = located_problems(type_, value)
        if problems:
            if isinstance(value, dict) and (type_ in POSE_AT or type_ == _PLANAR):
                problems = [_with_shorthand(type_, p) for p in problems]
            raise LiteralError(problems)
        fields = dict(value)
    return MessageLiteral(type_, _stamped(type_, fields))


def _is_shorthand(type_: str, value: dict[str, Any]) -> bool:
    if type_ == _PLANAR:
        return "yaw" in value
    if type_ not in POSE_AT:
        return False
    own = set(message_fields(type_))
    keys = set(map(str, value))
    if keys & own:
        if keys & {*_SHORTHAND, "frame_id"}:
            raise LiteralError([((), f"write either the fields of {type_} "
                                     f"({', '.join(sorted(keys & own))}) or the pose shorthand "
                                     f"({', '.join(sorted(keys - own))}), not both", False)])
        return False
    return bool(keys & {*_SHORTHAND, "frame_id"})


def _shorthand_keys(type_: str) -> tuple[str, ...]:
    if type_ == _PLANAR:
        return ("x", "y", "yaw")
    stamped = "header" in message_fields(type_)
    return (*_SHORTHAND, "frame_id") if stamped else _SHORTHAND


def _with_shorthand(
    type_: str, problem: tuple[LiteralPath, str, bool]
) -> tuple[LiteralPath, str, bool]:
    """Name the shorthand too when a top-level key is neither a field nor a shorthand key."""
    path, _text, at_key = problem
    if len(path) != 1 or not at_key:
        return problem
    keys = _shorthand_keys(type_)
    hint = did_you_mean(str(path[0]), (*message_fields(type_), *keys))
    return (path, f"neither a field of {type_} ({', '.join(message_fields(type_))}) nor a key "
                  f"of its pose shorthand ({', '.join(keys)}){hint}", True)


def _number(path: str, value: Any) -> tuple[float | None, list[tuple[LiteralPath, str, bool]]]:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None, [((path,), f"expected a number, got {value!r}", False)]
    return float(value), []


def _from_shorthand(type_: str, value: dict[str, Any]) -> dict[str, Any]:
    keys = _shorthand_keys(type_)
    problems: list[tuple[LiteralPath, str, bool]] = []
    numbers: dict[str, float] = {}
    for name, given in value.items():
        key = str(name)
        if key not in keys:
            problems.append(((key,), f"not a key of the pose shorthand of {type_}"
                                     f"{did_you_mean(key, keys)} (keys: {', '.join(keys)})",
                             True))
        elif key == "frame_id":
            if not isinstance(given, str) or not given:
                problems.append(((key,), f"expected a frame name, got {given!r}", False))
        else:
            number, wrong = _number(key, given)
            problems += wrong
            if number is not None:
                numbers[key] = number
    if problems:
        raise LiteralError(problems)
    return _pose_fields(type_, numbers, value.get("frame_id"))


def _pose_fields(type_: str, numbers: dict[str, float], frame: str | None) -> dict[str, Any]:
    x, y, yaw = numbers.get("x", 0.0), numbers.get("y", 0.0), numbers.get("yaw", 0.0)
    if type_ == _PLANAR:
        return {"x": x, "y": y, "theta": yaw}
    pose: dict[str, Any] = {
        "position": {"x": x, "y": y, "z": numbers.get("z", 0.0)},
        "orientation": {"x": 0.0, "y": 0.0, "z": math.sin(yaw / 2), "w": math.cos(yaw / 2)},
    }
    for name in reversed(POSE_AT[type_]):
        pose = {name: pose}
    if frame is not None:
        pose["header"] = {"frame_id": frame}
    return pose


def _from_text(type_: str, text: str) -> dict[str, Any]:
    parts = [part.strip() for part in text.split(";")]
    names = _NAV2_TEXT.get(type_)
    forms = []
    if names is not None:
        forms.append(";".join(names))
    if type_ in POSE_AT or type_ == _PLANAR:
        forms.append("x;y;yaw")
    if not forms:
        raise LiteralError([((), f"a {type_} has no text form: write its fields as a mapping "
                                 f"({', '.join(message_fields(type_))}) or bind an entry "
                                 "('{key}')", False)])
    if names is not None and len(parts) == len(names):
        return _nav2_fields(type_, names, parts, text)
    if len(parts) == 3 and "x;y;yaw" in forms:
        numbers = dict(zip(("x", "y", "yaw"), _numbers(parts, text, "x;y;yaw"), strict=True))
        return _pose_fields(type_, numbers, None)
    raise LiteralError([((), f"{text!r} is not a {type_}: expected "
                             f"{' or '.join(repr(f) for f in forms)}, or bind an entry "
                             "('{key}')", False)])


def _numbers(parts: list[str], text: str, form: str) -> list[float]:
    try:
        return [float(part) for part in parts]
    except ValueError:
        raise LiteralError([((), f"{text!r} ({form}): expected numbers", False)]) from None


def _nav2_fields(type_: str, names: tuple[str, ...], parts: list[str], text: str) -> dict[str, Any]:
    form = ";".join(names)
    if type_ != "geometry_msgs/msg/PoseStamped":
        return dict(zip(names, _numbers(parts, text, form), strict=True))
    stamp, frame, *rest = parts
    x, y, z, qx, qy, qz, qw = _numbers(rest, text, form)
    if not stamp.lstrip("-").isdigit():
        raise LiteralError([((), f"{text!r} ({form}): the stamp is in integer nanoseconds, "
                                 f"got '{stamp}'", False)])
    nanoseconds = int(stamp)
    return {"header": {"stamp": {"sec": nanoseconds // 10**9, "nanosec": nanoseconds % 10**9},
                       "frame_id": frame},
            "pose": {"position": {"x": x, "y": y, "z": z},
                     "orientation": {"x": qx, "y": qy, "z": qz, "w": qw}}}


def _stamped(type_: str, fields: dict[str, Any]) -> dict[str, Any]:
    """Fill a stamped message's header: frame ``map`` and stamp ``now`` unless given."""
    if message_fields(type_).get("header") != HEADER:
        return fields
    header = dict(fields.get("header") or {})
    header.setdefault("frame_id", "map")
    header.setdefault("stamp", "now")
    return {"header": header, **{k: v for k, v in fields.items() if k != "header"}}


def message_text(literal: MessageLiteral) -> str:
    """A literal as BT.CPP reads it in XML: Nav2's text form of its type, else ``json:``.

    A ``PoseStamped`` is ``stamp_ns;frame;x;y;z;qx;qy;qz;qw`` (a ``now`` stamp is written
    0, which Nav2 reads as "the latest"), a ``Point`` ``x;y;z``, a ``Quaternion``
    ``x;y;z;w``; another type is BT.CPP's ``json:`` form of its fields, which a BT.CPP
    node reads only when its type has a JSON converter.
    """
    import json

    fields = literal.fields
    if literal.type == "geometry_msgs/msg/PoseStamped":
        header, pose = fields.get("header", {}), fields.get("pose", {})
        stamp = header.get("stamp")
        nanoseconds = (stamp.get("sec", 0) * 10**9 + stamp.get("nanosec", 0)
                       if isinstance(stamp, dict) else 0)
        numbers = [*_ordered(pose.get("position", {}), "xyz"),
                   *_ordered(pose.get("orientation", {}), "xyzw")]
        return ";".join([str(nanoseconds), header.get("frame_id", ""), *numbers])
    if literal.type == "geometry_msgs/msg/Point":
        return ";".join(_ordered(fields, "xyz"))
    if literal.type == "geometry_msgs/msg/Quaternion":
        return ";".join(_ordered(fields, "xyzw"))
    return "json:" + json.dumps(fields, separators=(",", ":"))


def _ordered(fields: dict[str, Any], names: str) -> list[str]:
    """The numbers of ``names`` in order (a quaternion's ``w`` defaults to 1, as in its .msg)."""
    return [repr(float(fields.get(n, 1.0 if n == "w" and names == "xyzw" else 0.0)))
            for n in names]
