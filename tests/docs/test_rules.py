"""docs/reference/rules.md points at tests that exist (found with ast, not run)."""

from __future__ import annotations

import ast
import re
from functools import cache
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
RULES = REPO / "docs" / "reference" / "rules.md"
REFERENCE = re.compile(r"`(tests/[\w/]+\.py)::(\w+)(?:\[([\w-]+)\])?`")
RULE = re.compile(r"^### (R\d+)\. ", re.MULTILINE)


@cache
def defined_tests(path: Path) -> frozenset[str]:
    """Names of the test functions in a file, module level or in classes."""
    tree = ast.parse(path.read_text(), filename=str(path))
    return frozenset(node.name for node in ast.walk(tree)
                     if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef))
                     and node.name.startswith("test_"))


def test_every_referenced_test_exists() -> None:
    references = REFERENCE.findall(RULES.read_text())
    assert len(references) >= 28
    missing = []
    for file, name, case in references:
        path = REPO / file
        if not path.is_file():
            missing.append(f"{file} (no such file)")
        elif name not in defined_tests(path):
            missing.append(f"{file}::{name}")
        elif case and f'"{case}"' not in path.read_text():
            missing.append(f"{file}::{name}[{case}] (no such case)")
    assert missing == []


def test_every_rule_names_a_test() -> None:
    text = RULES.read_text()
    starts = [m.start() for m in RULE.finditer(text)]
    assert len(starts) >= 20
    numbers = RULE.findall(text)
    assert numbers == [f"R{i}" for i in range(1, len(numbers) + 1)], "rules are numbered in order"
    for number, start, end in zip(numbers, starts, [*starts[1:], len(text)], strict=True):
        assert REFERENCE.search(text[start:end]), f"{number} names no test"
