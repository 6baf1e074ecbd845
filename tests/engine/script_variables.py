"""A dict-backed Variables for the script tests (the real one is on py_trees' blackboard)."""

from __future__ import annotations

from typing import Any


class DictVariables(dict):
    """Variables in a plain dict: ``get`` raises KeyError when unset, as the protocol says."""

    def get(self, name: str) -> Any:  # type: ignore[override]
        return self[name]

    def set(self, name: str, value: Any) -> None:
        self[name] = value

    def unset(self, name: str) -> None:
        self.pop(name, None)
