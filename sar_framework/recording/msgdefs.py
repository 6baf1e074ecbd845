"""Schemas of a recording: the name each ROS type is stored under, and its definition.

Names: a message keeps its type name; a service event ``pkg/srv/Name_Event`` and an
action's ``pkg/action/Name_FeedbackMessage``, which ``mcap_ros2`` and ``rosbags`` refuse,
are stored as ``pkg/msg/NameEvent`` and ``pkg/msg/NameFeedbackMessage`` (same fields, same
bytes; docs/how-to/watch-a-run.md says why). Definitions: the installed interface files
(``share/<pkg>/msg/<Name>.msg``; the ``---``-separated parts of ``.srv`` and ``.action``
files) go into a ``rosbags`` type store, which writes the ``ros2msg`` text.
"""

from __future__ import annotations

import os
import re
import sys
from functools import cache
from pathlib import Path
from typing import Any

#: The parts of a ``.srv`` / ``.action`` file, by the suffix rosidl gives their types.
PARTS = {"srv": ("Request", "Response"), "action": ("Goal", "Result", "Feedback")}
#: The types rosidl wraps around a service's or an action's parts: suffix -> fields.
WRAPPERS = {
    "Event": "service_msgs/ServiceEventInfo info\n{base}_Request[<=1] request\n"
             "{base}_Response[<=1] response\n",
    "FeedbackMessage": "unique_identifier_msgs/UUID goal_id\n{base}_Feedback feedback\n",
}


class DefinitionError(LookupError):
    """An interface file needed for a definition is not installed."""


def share_dirs() -> list[Path]:
    """The ``share`` folders searched: ``AMENT_PREFIX_PATH`` entries, then this Python's."""
    prefixes = [p for p in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p]
    prefixes.append(sys.prefix)
    return [Path(p) / "share" for p in dict.fromkeys(prefixes)]


def schema_name(type_name: str) -> str:
    """The name a ROS type is stored under in a recording (see the module docstring).

    Args:
        type_name: A full ROS type name, e.g. ``std_srvs/srv/Trigger_Event``.

    Returns:
        ``type_name`` itself for a plain message, else the wrapper's ``pkg/msg/`` name
        without its underscore (``std_srvs/msg/TriggerEvent``).
    """
    package, kind, name = type_name.split("/")
    base, _, suffix = name.rpartition("_")
    if kind != "msg" and suffix in WRAPPERS:
        return f"{package}/msg/{base}{suffix}"
    return type_name


def _interface_text(package: str, kind: str, name: str) -> str:
    for share in share_dirs():
        path = share / package / kind / f"{name}.{kind}"
        if path.is_file():
            return path.read_text(encoding="utf-8")
    raise DefinitionError(f"{package}/{kind}/{name}.{kind} is not installed "
                          f"(searched {', '.join(str(s) for s in share_dirs())})")


def _source_text(store_name: str) -> str:
    """The ``.msg`` text of a type named ``pkg/msg/Name`` in the type store."""
    package, _, name = store_name.split("/")
    base, _, suffix = name.rpartition("_")
    kind = next((k for k, parts in PARTS.items() if base and suffix in parts), "msg")
    if kind == "msg":
        return _interface_text(package, "msg", name)
    sections = re.split(r"^---\s*$", _interface_text(package, kind, base), flags=re.MULTILINE)
    return sections[PARTS[kind].index(suffix)]


def _used(store: Any, store_name: str) -> list[str]:
    """The message types the fields of ``store_name`` use."""
    from rosbags.interfaces import Nodetype

    used = []
    for _field, (node, args) in store.fielddefs[store_name][1]:
        element, ref = args[0] if node in (Nodetype.ARRAY, Nodetype.SEQUENCE) else (node, args)
        if element == Nodetype.NAME:
            used.append(ref)
    return used


@cache
def _typestore() -> Any:
    from rosbags.typesys import Stores, get_typestore

    return get_typestore(Stores.EMPTY)


def _register(store_name: str, text: str) -> None:
    """Register a type and, from the installed files, every type it uses."""
    from rosbags.typesys import get_types_from_msg

    store = _typestore()
    pending = [(store_name, text)]
    while pending:
        name, source = pending.pop()
        if name in store.fielddefs:
            continue
        store.register(get_types_from_msg(source, name))
        pending.extend((dep, _source_text(dep)) for dep in _used(store, name)
                       if dep not in store.fielddefs)


def message_definition(type_name: str) -> str:
    """The full ``ros2msg`` definition stored for ``type_name`` (the type, then its uses).

    Args:
        type_name: A full ROS type name, e.g. ``tf2_msgs/msg/TFMessage`` or
            ``nav2_msgs/action/NavigateToPose_FeedbackMessage``.

    Returns:
        The definition text of :func:`schema_name` ``(type_name)``.

    Raises:
        DefinitionError: An interface file is not installed, or the type is not one a
            recording holds.
    """
    package, kind, name = type_name.split("/")
    stored = schema_name(type_name)
    base, _, suffix = name.rpartition("_")
    if stored != type_name:
        text = WRAPPERS[suffix].format(base=f"{package}/{base}")
    elif kind == "msg":
        text = _source_text(type_name)
    else:
        raise DefinitionError(f"unsupported interface type {type_name!r}")
    _register(stored, text)
    return str(_typestore().generate_msgdef(stored, ros_version=2)[0])
