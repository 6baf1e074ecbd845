"""Shared fixtures for the Nav2 package's tests."""

from __future__ import annotations

import pytest
from engine.conftest import GENERIC_PLUGINS, MISSION_PLUGINS

from sar_framework.engine.registry import Registry, discover


@pytest.fixture(scope="session")
def registry() -> Registry:
    """The engine tests' stand-in plugins and the Nav2 package (its controls and decorators)."""
    reg = discover([GENERIC_PLUGINS, MISSION_PLUGINS, "sar_plugins.nav2"], builtins=False,
                   entry_points=False)
    assert reg.diagnostics == []
    return reg
