"""Message definition text for MCAP schemas, as rosbag2 writes it (encoding ``ros2msg``).

A definition is the type's own ``.msg`` text followed by every type it uses, each after a
separator line and ``MSG: pkg/Name``. The text comes from the interface files installed
with the packages (``<prefix>/share/<pkg>/msg/<Name>.msg``, ``srv/``, ``action/``), the
files a ROS install or this project's ``.venv`` holds. Service events
(``pkg/srv/Name_Event``) and action feedback messages
(``pkg/action/Name_FeedbackMessage``) are built from the ``.srv`` / ``.action`` parts the
way rosidl generates them.
"""

from __future__ import annotations

import os
import re
import sys
from functools import cache
from pathlib import Path

SEPARATOR = "=" * 80
_PRIMITIVES = frozenset({
    "bool", "byte", "char", "float32", "float64", "int8", "uint8", "int16", "uint16",
    "int32", "uint32", "int64", "uint64", "string", "wstring",
})
_FIELD = re.compile(r"^\s*([A-Za-z][A-Za-z0-9_/]*)(\[[^\]]*\])?(<=\d+)?\s+\w+")


class DefinitionError(LookupError):
    """An interface file needed for a definition is not installed."""


def share_dirs() -> list[Path]:
    """The ``share`` folders searched: ``AMENT_PREFIX_PATH`` entries, then this Python's."""
    prefixes = [p for p in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p]
    prefixes.append(sys.prefix)
    return [Path(p) / "share" for p in dict.fromkeys(prefixes)]


@cache
def _interface_text(package: str, kind: str, name: str) -> str:
    for share in share_dirs():
        path = share / package / kind / f"{name}.{kind}"
        if path.is_file():
            return path.read_text(encoding="utf-8")
    raise DefinitionError(f"{package}/{kind}/{name}.{kind} is not installed "
                          f"(searched {', '.join(str(s) for s in share_dirs())})")


def _parts(package: str, kind: str, name: str) -> list[str]:
    """The ``---``-separated parts of a ``.srv`` or ``.action`` file."""
    return re.split(r"^---\s*$", _interface_text(package, kind, name), flags=re.MULTILINE)


def own_text(type_name: str) -> str:
    """The ``.msg``-style text of one type (``pkg/msg/Name``, ``pkg/srv/Name_Request``...).

    Args:
        type_name: A full type name.

    Returns:
        The type's fields as ``.msg`` text.

    Raises:
        DefinitionError: The interface file is not installed.
    """
    package, kind, name = type_name.split("/")
    if kind == "msg":
        return _interface_text(package, "msg", name)
    base, _, suffix = name.rpartition("_")
    if kind == "srv":
        if suffix in ("Request", "Response"):
            return _parts(package, "srv", base)[0 if suffix == "Request" else 1]
        if suffix == "Event":
            return (f"service_msgs/ServiceEventInfo info\n"
                    f"{package}/{base}_Request[<=1] request\n"
                    f"{package}/{base}_Response[<=1] response\n")
    if kind == "action":
        parts = {"Goal": 0, "Result": 1, "Feedback": 2}
        if suffix in parts:
            return _parts(package, "action", base)[parts[suffix]]
        if name.endswith("_FeedbackMessage"):
            base = name[: -len("_FeedbackMessage")]
            return (f"unique_identifier_msgs/UUID goal_id\n"
                    f"{package}/{base}_Feedback feedback\n")
    raise DefinitionError(f"unsupported interface type {type_name!r}")


def _kind_of(name: str) -> str:
    """``srv`` or ``action`` for the parts rosidl generates from those files, else ``msg``."""
    suffix = name.rpartition("_")[2]
    if suffix in ("Request", "Response"):
        return "srv"
    return "action" if suffix in ("Goal", "Result", "Feedback") else "msg"


def _used_types(text: str, package: str, kind: str) -> list[str]:
    """Full names of the non-primitive field types in ``text`` (in order, no repeats)."""
    used: list[str] = []
    for line in text.splitlines():
        match = _FIELD.match(line.split("#", 1)[0])
        if not match:
            continue
        field_type = match.group(1)
        if field_type in _PRIMITIVES:
            continue
        if "/" in field_type:
            dep_package, dep_name = field_type.split("/")[0], field_type.split("/")[-1]
            full = f"{dep_package}/{_kind_of(dep_name)}/{dep_name}"
        else:
            full = f"{package}/{kind}/{field_type}"
        if full not in used:
            used.append(full)
    return used


def message_definition(type_name: str) -> str:
    """The full ``ros2msg`` definition of ``type_name`` (the type, then its dependencies).

    Args:
        type_name: For example ``tf2_msgs/msg/TFMessage``.

    Returns:
        The concatenated definition text.

    Raises:
        DefinitionError: An interface file is not installed.
    """
    sections = [own_text(type_name).strip()]
    seen = {type_name}
    package, kind, _ = type_name.split("/")
    queue = _used_types(sections[0], package, kind)
    while queue:
        dep = queue.pop(0)
        if dep in seen:
            continue
        seen.add(dep)
        text = own_text(dep).strip()
        dep_package, dep_kind, dep_name = dep.split("/")
        sections.append(f"{SEPARATOR}\nMSG: {dep_package}/{dep_name}\n{text}")
        queue.extend(_used_types(text, dep_package, dep_kind))
    return "\n".join(sections) + "\n"
