"""The search-and-rescue app: zones, survivors and their servers, on the neutral core.

Registered under the entry-point group ``sar_framework.apps`` (``pyproject.toml``) and
found here too (``APP``), as any app in a tree's ``plugins:`` is.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from sar_plugins.sar.app import APP

__all__ = ["APP"]


def __getattr__(name: str) -> Any:
    """``APP`` on first use: the app's servers import this package but need none of it."""
    if name == "APP":
        from sar_plugins.sar.app import APP

        return APP
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
