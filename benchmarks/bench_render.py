"""Benchmark tree rendering: DOT source, SVG (via Graphviz ``dot``) and Unicode text.

Builds synthetic validated trees (mixed composites, decorators, leaves with
params, references and subtrees) and prints the median wall time per format::

    .venv/bin/python benchmarks/bench_render.py               # 100, 1000, 2000, 5000 nodes
    .venv/bin/python benchmarks/bench_render.py --sizes 1000 --runs 10
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

from sar_framework.engine.diagnostics import SourceLocation
from sar_framework.engine.rendering.render import render_dot, render_text, render_to_file
from sar_framework.engine.spec import Category, NodeSpec, TreeSpec

_DECORATORS: list[tuple[str, dict[str, object]]] = [
    ("one_shot", {"policy": "on_completion"}),
    ("retry", {"num_failures": 3}),
    ("timeout", {"duration": 5.0}),
    ("inverter", {}),
    ("failure_is_success", {}),
]


def synthetic_tree(size: int, fanout: int = 4) -> TreeSpec:
    """Build a tree of exactly ``size`` nodes, breadth first, with varied kinds.

    Args:
        size: Number of nodes (>= 1).
        fanout: Children per composite.

    Returns:
        A TreeSpec shaped like a real mission tree, only bigger.
    """
    loc = SourceLocation("bench.yaml", 1, 1)
    root = NodeSpec("sequence", Category.COMPOSITE, "Root", "0", loc, {"memory": True})
    count = 1
    frontier = [root]
    while count < size:
        parent = frontier.pop(0)
        wanted = 1 if parent.category is Category.DECORATOR else fanout
        for _ in range(min(wanted, size - count)):
            index = len(parent.children)
            uid = f"{parent.uid}.{index}"
            remaining = size - count
            choice = count % 7
            if remaining <= 2 or choice in (0, 1, 2):
                node = NodeSpec(
                    "DetectSurvivor" if count % 2 else "NavigateToZone",
                    Category.LEAF,
                    f"Leaf {count}?",
                    uid,
                    loc,
                    {"timeout_s": 10.0, "zone": f"zone_{count}", "retries": 2},
                    id=f"leaf{count}",
                )
                # References stay local, as in real trees: a leaf reads an
                # earlier sibling (IsSurvivorDetected -> DetectSurvivor).
                siblings = [c for c in parent.children if c.category is Category.LEAF]
                if siblings and count % 3 == 0:
                    target = siblings[-1]
                    node.attrs["detector"] = target.id
                    node.refs["detector"] = target
            elif choice in (3, 4):
                kind, attrs = _DECORATORS[count % len(_DECORATORS)]
                node = NodeSpec(kind, Category.DECORATOR, f"Dec {count}", uid, loc, dict(attrs))
                frontier.append(node)
            else:
                kind = ("sequence", "selector", "parallel")[count % 3]
                attrs: dict[str, object] = (
                    {"policy": "success_on_all", "synchronise": True}
                    if kind == "parallel"
                    else {"memory": bool(count % 2)}
                )
                node = NodeSpec(kind, Category.COMPOSITE, f"Comp {count}", uid, loc, attrs)
                if count % 11 == 0:
                    node.subtree = f"sub{count}"
                frontier.append(node)
            parent.children.append(node)
            count += 1
        if not frontier and count < size:
            raise RuntimeError("generator ran out of open composites")
    # A decorator left without a child (the tree ran out) gets a leaf; the
    # count stays close to ``size`` and the tree stays valid-shaped.
    for node in list(frontier):
        if node.category is Category.DECORATOR and not node.children:
            node.children.append(
                NodeSpec("Dwell", Category.LEAF, "Dwell", f"{node.uid}.0", loc, {"duration": 1.0})
            )
    return TreeSpec("bench", "synthetic benchmark tree", root, "bench.yaml")


def median_ms(action: Callable[[], object], runs: int) -> float:
    """Return the median wall time of ``action`` in milliseconds."""
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        action()
        times.append((time.perf_counter() - start) * 1000.0)
    return statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[100, 1000, 2000, 5000])
    parser.add_argument("--runs", type=int, default=5)
    args = parser.parse_args()

    print(f"{'nodes':>6}  {'format':<8}  {'median ms':>10}  runs")
    with tempfile.TemporaryDirectory() as tmp:
        for size in args.sizes:
            spec = synthetic_tree(size)
            nodes = len(spec)
            svg = Path(tmp) / f"tree{size}.svg"
            svg_runs = args.runs if nodes <= 2000 else 1
            cases: list[tuple[str, Callable[[], object], int]] = [
                ("dot", lambda spec=spec: render_dot(spec), args.runs),
                ("unicode", lambda spec=spec: render_text(spec), args.runs),
                # dot's layout grows superlinearly: big trees get a single run.
                ("svg", lambda spec=spec, svg=svg: render_to_file(spec, svg), svg_runs),
            ]
            for fmt, action, runs in cases:
                print(f"{nodes:>6}  {fmt:<8}  {median_ms(action, runs):>10.1f}  {runs}")


if __name__ == "__main__":
    main()
