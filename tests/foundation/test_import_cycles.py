"""No import cycle between modules, nor between packages, in sar_framework and plugins.

The graph is read from the source with :mod:`ast` (nothing is imported): every ``import``
and ``from ... import`` counts, at module level, inside functions (lazy imports) and under
``TYPE_CHECKING`` alike, since each one is a dependency a reader has to follow.

- Module graph: ``a -> b`` when module ``a`` imports module ``b`` (``from p import name``
  points at ``p.name`` when that is a module, else at ``p``).
- Package graph, at every level: within a package ``P``, each child (a module, or a
  subpackage with everything below it) is one node, and ``x -> y`` when something in ``x``
  imports something in ``y``. A cycle there that goes through a subpackage is a package
  cycle (one made of plain modules is already a module cycle).
"""

from __future__ import annotations

import ast
from collections.abc import Iterable, Iterator
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SOURCES = {"sar_framework": ROOT / "sar_framework", "sar_plugins": ROOT / "plugins"}

Graph = dict[str, set[str]]


def _modules() -> dict[str, Path]:
    """Every module's dotted name -> its file (a package is named by its ``__init__``)."""
    modules = {}
    for top, folder in SOURCES.items():
        for path in sorted(folder.rglob("*.py")):
            parts = [top, *path.relative_to(folder).with_suffix("").parts]
            if parts[-1] == "__init__":
                parts.pop()
            modules[".".join(parts)] = path
    return modules


def _imported(name: str, path: Path, tree: ast.AST, modules: Iterable[str]) -> Iterator[str]:
    """The modules of ours that ``tree`` (module ``name``, file ``path``) imports."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            yield from (alias.name for alias in node.names if alias.name in modules)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[:len(package.split(".")) - node.level + 1]
                origin = ".".join(base + ([node.module] if node.module else []))
            else:
                origin = node.module or ""
            for alias in node.names:
                yield f"{origin}.{alias.name}" if f"{origin}.{alias.name}" in modules else origin


def module_graph() -> Graph:
    """Module -> the modules of ours it imports."""
    modules = _modules()
    graph: Graph = {}
    for name, path in modules.items():
        tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
        graph[name] = {target for target in _imported(name, path, tree, modules)
                       if target in modules and target != name}
    return graph


def _child(package: str, module: str) -> str:
    """The child of ``package`` that holds ``module`` (``package.__init__`` for itself)."""
    if module == package:
        return package + ".__init__"
    rest = module[len(package) + 1:].split(".")
    return f"{package}.{rest[0]}"


def package_graphs(modules: Graph) -> dict[str, Graph]:
    """Package -> the graph between its children (subpackages collapsed)."""
    packages = {name for name in modules if any(m.startswith(name + ".") for m in modules)}
    graphs: dict[str, Graph] = {package: {} for package in packages}
    for source, targets in modules.items():
        for target in targets:
            common = [a for a, b in zip(source.split("."), target.split("."), strict=False)
                      if a == b]
            # the deepest package holding both (a common prefix is a package by construction)
            while common and ".".join(common) not in packages:
                common.pop()
            package = ".".join(common)
            if not package:
                continue  # sar_framework <-> sar_plugins: checked as modules
            a, b = _child(package, source), _child(package, target)
            if a != b:
                graphs[package].setdefault(a, set()).add(b)
    return graphs


def cycles(graph: Graph) -> list[list[str]]:
    """One concrete cycle per strongly connected component of more than one node."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    components: list[set[str]] = []

    def visit(node: str) -> None:  # Tarjan; graphs here are a few hundred nodes deep at most
        index[node] = low[node] = len(index)
        stack.append(node)
        on_stack.add(node)
        for nxt in graph.get(node, ()):
            if nxt not in index:
                visit(nxt)
                low[node] = min(low[node], low[nxt])
            elif nxt in on_stack:
                low[node] = min(low[node], index[nxt])
        if low[node] == index[node]:
            component = set()
            while True:
                member = stack.pop()
                on_stack.discard(member)
                component.add(member)
                if member == node:
                    break
            if len(component) > 1:
                components.append(component)

    for node in sorted(graph):
        if node not in index:
            visit(node)
    return [_cycle_in(graph, component) for component in components]


def _cycle_in(graph: Graph, component: set[str]) -> list[str]:
    """A shortest cycle through the component's first node (breadth first)."""
    start = min(component)
    paths = {start: [start]}
    queue = [start]
    while queue:
        node = queue.pop(0)
        for nxt in sorted(graph.get(node, ())):
            if nxt == start:
                return [*paths[node], start]
            if nxt in component and nxt not in paths:
                paths[nxt] = [*paths[node], nxt]
                queue.append(nxt)
    raise AssertionError(f"no cycle through {start}")  # a component always has one


def _worded(found: Iterable[list[str]]) -> str:
    return "\n".join(" -> ".join(cycle) for cycle in found)


def test_no_module_imports_itself_back() -> None:
    found = cycles(module_graph())
    assert not found, "module import cycles:\n" + _worded(found)


def test_no_package_imports_itself_back() -> None:
    modules = module_graph()
    graphs = package_graphs(modules)
    found = [cycle for graph in graphs.values() for cycle in cycles(graph)
             if any(node in graphs for node in cycle)]
    assert not found, "package import cycles:\n" + _worded(found)


def test_the_checks_see_a_cycle() -> None:
    graph = {"p.a": {"p.b"}, "p.b": {"p.c"}, "p.c": {"p.a"}, "p.d": {"p.a"}}
    assert cycles(graph) == [["p.a", "p.b", "p.c", "p.a"]]
    graphs = package_graphs({"p": set(), "p.x": set(), "p.x.m": {"p.y.n"},
                             "p.y": set(), "p.y.n": {"p.x"}})
    assert cycles(graphs["p"]) == [["p.x", "p.y", "p.x"]]
