"""The search-and-rescue app: zones, survivors and their servers, on the neutral core.

Registered under the entry-point group ``sar_framework.apps`` (``pyproject.toml``) and
found here too (``APP``), as any app in a tree's ``plugins:`` is.
"""

from sar_plugins.sar.app import APP

__all__ = ["APP"]
