"""Every tree file in the repository validates against the built-in plugins and the
search-and-rescue app's leaves."""

from __future__ import annotations

from pathlib import Path

import pytest

from sar_framework.engine.api import validate
from sar_framework.engine.registry import discover

from .conftest import REPO

TREES = sorted((REPO / "trees").rglob("*.yaml"))


@pytest.mark.parametrize("path", TREES, ids=[str(p.relative_to(REPO)) for p in TREES])
def test_repo_tree_is_valid(path: Path) -> None:
    # the core's leaves and the search-and-rescue app's, which the repository's trees use
    result = validate(path, registry=discover(["sar_plugins.sar.leaves"], entry_points=False))
    assert [str(d) for d in result.diagnostics] == []
    assert result.spec is not None or result.library
