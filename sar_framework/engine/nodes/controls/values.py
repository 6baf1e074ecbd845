"""Variables held in a plain dict, with write versions: for unit tests.

:class:`DictVariables` is the smallest :class:`~sar_framework.engine.variables.Variables`:
tests give it to the blackboard nodes. Like
:class:`~sar_framework.engine.variables.BlackboardVariables` it counts writes per name
(``version``), which SkipUnlessUpdated and WaitValueUpdate read.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any


class DictVariables:
    """Named values in a dict, each with a count of its writes.

    Args:
        initial: The starting values (each counts as written once).
    """

    def __init__(self, initial: Mapping[str, Any] | None = None) -> None:
        self.values: dict[str, Any] = {}
        self.versions: dict[str, int] = {}
        for name, value in (initial or {}).items():
            self.set(name, value)

    def get(self, name: str) -> Any:
        """Return the value of ``name``; raise KeyError when it has none."""
        return self.values[name]

    def set(self, name: str, value: Any) -> None:
        """Give ``name`` a value (a new version, even when equal to the old one)."""
        self.values[name] = value
        self.versions[name] = self.versions.get(name, 0) + 1

    def unset(self, name: str) -> None:
        """Remove ``name``'s value and its version."""
        self.values.pop(name, None)
        self.versions.pop(name, None)

    def __contains__(self, name: str) -> bool:
        """Whether ``name`` has a value."""
        return name in self.values

    def version(self, name: str) -> int:
        """How many times ``name`` was written since it was last unset (0: never)."""
        return self.versions.get(name, 0)
