"""docs/architecture.md and the engine agree: what the page names exists, and the page
names every engine package."""

from __future__ import annotations

import re
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
PAGE = (REPO / "docs" / "architecture.md").read_text(encoding="utf-8")
ENGINE = REPO / "sar_framework" / "engine"
ENGINE_PATH = re.compile(r"(?<![\w/])(?:sar_framework/)?engine/[\w/]*(?:\.py\b)?")
ENTRY = re.compile(r"^( *)(\w+(?:\.py|/))(?=\s|$)")


def engine_listing() -> list[str]:
    """Every module and package the page's engine listing names, as paths in the repo."""
    block = PAGE.split("## The engine", 1)[1].split("```", 2)[1]
    named: list[str] = []
    stack: list[tuple[int, str]] = [(-1, "sar_framework")]
    for line in block.splitlines():
        match = ENTRY.match(line)
        if not match:
            continue
        indent, name = len(match.group(1)), match.group(2)
        while stack[-1][0] >= indent:
            stack.pop()
        path = f"{stack[-1][1]}/{name.rstrip('/')}"
        named.append(path)
        if name.endswith("/"):
            stack.append((indent, path))
    return named


def test_the_listing_is_read() -> None:
    named = engine_listing()
    assert "sar_framework/engine/checking/validate.py" in named
    assert "sar_framework/engine/nodes/controls" in named


def test_every_module_and_package_the_page_names_exists() -> None:
    named = engine_listing()
    named += [("" if p.startswith("sar_framework/") else "sar_framework/") + p.rstrip("/")
              for p in ENGINE_PATH.findall(PAGE)]
    assert not [path for path in named if not (REPO / path).exists()]


def test_the_page_names_every_engine_package() -> None:
    named = set(engine_listing())
    packages = {str(init.parent.relative_to(REPO)) for init in ENGINE.rglob("__init__.py")}
    assert packages - named == set()
