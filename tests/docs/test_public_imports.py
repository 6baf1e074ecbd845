"""The names the tutorials and the docs import, from the paths they import them from.

Plugins written against the documented API import these; a move inside the engine must
leave every one importable where the docs say it is.
"""

from __future__ import annotations

import ast
import importlib
import re
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parents[2] / "docs"
PYTHON = re.compile(r"^```python\n(.*?)^```", re.MULTILINE | re.DOTALL)
IMPORT = re.compile(r"^(?:from sar_\S+ import (?:\([^)]*\)|.*)|import sar_.*)$", re.MULTILINE)

#: What docs/tutorials import (a floor: the scan below must find at least these).
TUTORIALS = {
    "sar_framework": {"load_tree", "load_spec"},
    "sar_framework.engine.plugin": {"Param", "leaf"},
    "sar_framework.engine.ports": {"BidirectionalPort", "InputPort", "OutputPort"},
    "sar_framework.engine.api": {"TreeLoadError"},
    "sar_framework.testing": {"assert_feedback", "assert_status", "assert_statuses"},
}


def imports_in_docs() -> dict[str, set[str]]:
    """Module -> the names the docs' python blocks import from it."""
    found: dict[str, set[str]] = {}
    for page in sorted(DOCS.rglob("*.md")):
        for block in PYTHON.findall(page.read_text(encoding="utf-8")):
            text = "\n".join(IMPORT.findall(block.replace("\\\n", " ")))
            for node in ast.walk(ast.parse(text)):
                if isinstance(node, ast.ImportFrom) and node.module:
                    found.setdefault(node.module, set()).update(a.name for a in node.names)
                elif isinstance(node, ast.Import):
                    found.update({a.name: set() for a in node.names})
    return found


def test_the_scan_finds_what_the_tutorials_import() -> None:
    found = imports_in_docs()
    missing = {module: names - found.get(module, set()) for module, names in TUTORIALS.items()}
    assert not any(missing.values()), missing


@pytest.mark.parametrize(("module", "names"), sorted(
    (module, sorted(names)) for module, names in {**imports_in_docs(), **TUTORIALS}.items()))
def test_documented_names_import_from_their_documented_paths(module: str,
                                                             names: list[str]) -> None:
    imported = importlib.import_module(module)
    absent = [name for name in names if not hasattr(imported, name)]
    assert not absent, f"{module} has no {absent}"
