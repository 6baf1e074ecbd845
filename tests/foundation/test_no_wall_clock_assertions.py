"""The suite asserts nothing about wall-clock time: a grep finds only outer safety bounds.

A test waits for what it means (an event, a status, a message, a simulated time) under one
generous bound. Every comparison that involves the wall clock (``time.monotonic``,
``time.time``, ``time.perf_counter`` or a value computed from one, in the same module) must
carry the comment ``# outer safety bound`` on one of its lines: the bound a wait gives up
at, never a figure the test checks. Timing promises are measured by benchmarks/.

    grep -rnE "monotonic|time\\.time|perf_counter" tests sar_framework/testing

lists them all; this test reads every module of ``tests/`` and of the public testing kit
(``sar_framework/testing``) with :mod:`ast` and names each unmarked comparison.
"""

from __future__ import annotations

import ast
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
SCANNED = (REPO / "tests", REPO / "sar_framework" / "testing")
MARK = "outer safety bound"
CLOCKS = frozenset({"monotonic", "monotonic_ns", "time", "time_ns", "perf_counter",
                    "perf_counter_ns"})
_NAMED = frozenset({"monotonic", "monotonic_ns", "perf_counter", "perf_counter_ns"})


def _is_clock_call(node: ast.AST) -> bool:
    if not isinstance(node, ast.Call):
        return False
    func = node.func
    if isinstance(func, ast.Attribute):
        return (func.attr in CLOCKS and isinstance(func.value, ast.Name)
                and func.value.id == "time")
    return isinstance(func, ast.Name) and func.id in _NAMED


def _walk(scope: ast.AST) -> list[ast.AST]:
    """The nodes of ``scope``: a function's all; the module's outside every function."""
    if not isinstance(scope, ast.Module):
        return list(ast.walk(scope))
    nodes, todo = [], [scope]
    while todo:
        node = todo.pop()
        nodes.append(node)
        todo.extend(child for child in ast.iter_child_nodes(node)
                    if not isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)))
    return nodes


def _key(node: ast.AST) -> str | None:
    """``name`` for a name, ``self.attr`` for an attribute of ``self``, else None."""
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) \
            and node.value.id == "self":
        return "self." + node.attr
    return None


class _Clocks:
    """The clock values of one module: names per function, ``self.`` attributes, functions."""

    def __init__(self, tree: ast.Module) -> None:
        self.scopes: list[ast.AST] = [tree] + [
            n for n in ast.walk(tree) if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))]
        self.names: dict[int, set[str]] = {id(scope): set() for scope in self.scopes}
        self.attributes: set[str] = set()
        self.functions: set[str] = set()
        while self._grow():
            pass

    def uses_clock(self, node: ast.AST, scope: ast.AST) -> bool:
        """Whether ``node`` reads a clock, or a value computed from one, in ``scope``."""
        names = self.names[id(scope)]
        for sub in ast.walk(node):
            if _is_clock_call(sub):
                return True
            if isinstance(sub, ast.Call) and isinstance(sub.func, ast.Name) \
                    and sub.func.id in self.functions:
                return True
            key = _key(sub)
            if key is not None and isinstance(getattr(sub, "ctx", None), ast.Load) \
                    and (key in names or key in self.attributes):
                return True
        return False

    def _grow(self) -> bool:
        before = (sum(map(len, self.names.values())), len(self.attributes), len(self.functions))
        for scope in self.scopes:
            for node in _walk(scope):
                if isinstance(node, (ast.Assign, ast.AnnAssign, ast.AugAssign)) \
                        and node.value is not None and self.uses_clock(node.value, scope):
                    targets = node.targets if isinstance(node, ast.Assign) else [node.target]
                    for part in (p for t in targets for p in ast.walk(t)):
                        key = _key(part)
                        if key is not None and isinstance(getattr(part, "ctx", None), ast.Store):
                            (self.attributes if key.startswith("self.")
                             else self.names[id(scope)]).add(key)
            if isinstance(scope, (ast.FunctionDef, ast.AsyncFunctionDef)) and any(
                    isinstance(r, ast.Return) and r.value is not None
                    and self.uses_clock(r.value, scope) for r in _walk(scope)):
                self.functions.add(scope.name)
        after = (sum(map(len, self.names.values())), len(self.attributes), len(self.functions))
        return after != before


def unmarked_comparisons(source: str) -> list[tuple[int, str]]:
    """``(line, text)`` of every wall-clock comparison without the outer-safety-bound mark.

    Args:
        source: A Python module's text.
    """
    tree = ast.parse(source)
    lines = source.splitlines()
    clocks = _Clocks(tree)
    found = set()
    for scope in clocks.scopes:
        for node in _walk(scope):
            if not isinstance(node, ast.Compare) or not clocks.uses_clock(node, scope):
                continue
            span = lines[node.lineno - 1:(node.end_lineno or node.lineno)]
            if not any("#" in line and MARK in line.split("#", 1)[1] for line in span):
                found.add((node.lineno, lines[node.lineno - 1].strip()))
    return sorted(found)


def test_every_wall_clock_comparison_is_a_marked_outer_safety_bound() -> None:
    offenders = []
    for folder in SCANNED:
        for path in sorted(folder.rglob("*.py")):
            for line, text in unmarked_comparisons(path.read_text(encoding="utf-8")):
                offenders.append(f"{path.relative_to(REPO)}:{line}: {text}")
    assert not offenders, (
        "wall-clock comparisons that are not marked '# outer safety bound' (wait for an "
        "event, a status or a simulated time instead; timing figures go to benchmarks/):\n"
        + "\n".join(offenders))


def test_the_scan_finds_what_it_must() -> None:
    """The check can fail: direct, derived and returned clock values are all caught."""
    flagged = """
import time
from time import perf_counter

def took():
    start = time.monotonic()
    return time.monotonic() - start

def check(thing):
    assert took() < 1.0
    sent = time.time()
    thing()
    waited = time.time() - sent
    assert waited < 2.0
    assert perf_counter() > 0
    self.started = time.monotonic()
    assert time.monotonic() - self.started <= 5  # a comment that is no mark
"""
    assert [line for line, _ in unmarked_comparisons(flagged)] == [10, 14, 15, 17]
    marked = """
import time

def wait(ready):
    deadline = time.monotonic() + 60  # outer safety bound (about 1 s expected)
    while not ready() and time.monotonic() < deadline:  # outer safety bound
        time.sleep(0.01)
    assert ready(), "not ready within the outer safety bound"
    count = 3
    assert count < 4
"""
    assert unmarked_comparisons(marked) == []


PAGE_CLOCKS = ("performance.now(", "Date.now(")


def page_clock_reads(source: str) -> list[int]:
    """The lines of ``source`` whose page script reads the browser's clock."""
    return [number for number, line in enumerate(source.splitlines(), 1)
            if any(clock in line for clock in PAGE_CLOCKS)]


def test_no_page_script_in_the_suite_reads_the_browsers_clock() -> None:
    """A page's timing is a figure for benchmarks/bench_studio.py; a test counts instead."""
    offenders = [f"{path.relative_to(REPO)}:{line}"
                 for root in SCANNED for path in sorted(root.rglob("*.py"))
                 if path.name != Path(__file__).name
                 for line in page_clock_reads(path.read_text())]
    assert not offenders, f"page scripts timing themselves in the suite: {offenders}"


def test_the_page_scan_finds_what_it_must() -> None:
    script = 'SCRIPT = """\nlet began = performance.now();\nrun();\nreturn Date.now() - t;\n"""\n'
    assert page_clock_reads(script) == [2, 4]
