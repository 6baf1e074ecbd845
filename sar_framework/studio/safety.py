"""What keeps the studio harmless: a session token, confined paths, checked messages.

- The server binds ``127.0.0.1`` unless told otherwise (:data:`DEFAULT_HOST`).
- A token made at start (:func:`new_token`) is printed in the URL, as Jupyter does;
  whatever writes (saving a file, reloading a running mission) must present it
  (:func:`token_ok`, constant-time). Reading needs none: the page only shows what the
  machine's own ROS graph or files already hold.
- A path the page names is resolved and must lie under one of the roots (the project
  and the directories given on the command line): :func:`confine`.
- A websocket message is at most :data:`MESSAGE_MAX_BYTES`, JSON, an object with a known
  ``op`` and fields of the right types (:func:`parse_message`); anything else is answered
  with an error and changes nothing.
"""

from __future__ import annotations

import hmac
import json
import math
import secrets
from collections.abc import Iterable
from pathlib import Path
from typing import Any

DEFAULT_HOST = "127.0.0.1"
#: Largest websocket message (and upload) accepted, in bytes.
MESSAGE_MAX_BYTES = 64 * 1024
#: ``op`` -> the fields it takes and their types.
MESSAGES: dict[str, dict[str, type | tuple[type, ...]]] = {
    "seek": {"t": (int, float)},
    "node": {"uid": str},
    "hello": {},
    "ack": {},
    "check": {"text": str},
}
#: Longest string per field (a uid, or a tree's whole text).
_STRING_MAX = {"text": MESSAGE_MAX_BYTES}
_UID_MAX = 200


class RefusedError(ValueError):
    """A request the studio will not act on (the message says why)."""


def new_token() -> str:
    """A fresh session token (48 hex digits)."""
    return secrets.token_hex(24)


def token_ok(given: str | None, token: str) -> bool:
    """Whether ``given`` is the session token (compared in constant time)."""
    return given is not None and hmac.compare_digest(given.encode(), token.encode())


def confine(path: str | Path, roots: Iterable[Path]) -> Path:
    """``path`` resolved, if it lies under one of ``roots``.

    Args:
        path: The path asked for (relative ones are taken from the first root).
        roots: The directories the studio may read and write in.

    Returns:
        The resolved path.

    Raises:
        RefusedError: It lies outside every root (``..``, symbolic links and absolute paths
            included).
    """
    roots = [Path(r).resolve() for r in roots]
    if not roots:
        raise RefusedError("no directory is open to the studio")
    candidate = Path(path)
    if not candidate.is_absolute():
        candidate = roots[0] / candidate
    resolved = candidate.resolve()
    if not any(resolved == r or r in resolved.parents for r in roots):
        raise RefusedError(f"{path}: outside the directories open to the studio "
                      f"({', '.join(str(r) for r in roots)})")
    return resolved


def parse_message(text: str | bytes) -> dict[str, Any]:
    """Check one websocket message from the page.

    Args:
        text: The raw message.

    Returns:
        The message: an object with a known ``op`` and its fields.

    Raises:
        RefusedError: Too long, not JSON, not an object, an unknown ``op``, or a field missing,
            unknown or of the wrong type.
    """
    if len(text) > MESSAGE_MAX_BYTES:
        raise RefusedError(f"message of {len(text)} bytes; at most {MESSAGE_MAX_BYTES}")
    try:
        message = json.loads(text)
    except (ValueError, UnicodeDecodeError) as err:
        raise RefusedError(f"not JSON: {err}") from None
    if not isinstance(message, dict):
        raise RefusedError("a message is a JSON object")
    op = message.get("op")
    if not isinstance(op, str) or op not in MESSAGES:
        raise RefusedError(f"unknown op {op!r}; known: {', '.join(sorted(MESSAGES))}")
    fields = MESSAGES[op]
    extra = set(message) - set(fields) - {"op"}
    if extra:
        raise RefusedError(f"{op}: unknown field(s) {', '.join(sorted(extra))}")
    for name, kinds in fields.items():
        value = message.get(name)
        if isinstance(value, bool) or not isinstance(value, kinds):
            raise RefusedError(f"{op}: {name} missing or of the wrong type")
        if isinstance(value, float) and not math.isfinite(value):
            raise RefusedError(f"{op}: {name} must be finite")
        if isinstance(value, str) and len(value) > _STRING_MAX.get(name, _UID_MAX):
            raise RefusedError(f"{op}: {name} too long")
    return message
