"""Benchmark the tree engine with the figures a user feels.

Rows (median of the runs; the minimum beside it, what the code costs when nothing else
competes for the CPU):

* ``sar-tree validate`` of trees/search_and_rescue.yaml, the whole process, against
  ``python -c "import yaml, jsonschema"`` (the two libraries validation needs), the
  commands alternating so that they share the machine's noise; the ratio is context, not a
  goal (a validate of about 150 ms is not a cost a user feels). Twice:
  without ``.pyc`` files for sources that have none (``PYTHONDONTWRITEBYTECODE=1`` and an
  editable install: ours are compiled on every run) and with them (as a regular install
  has). Beside it, for scale: the floor plus the built-in plugins (what validating must
  import, since it imports every plugin module to read its declarations), the floor plus
  py_trees, the floor plus the engine's and CLI's own modules (no plugin, no py_trees), the
  bare interpreter and, with ``--baseline``, another ``sar-tree``;
* ``load_tree`` (read + validate + build, in-process) of the reference tree (goal <= 5 ms)
  and of a synthetic 100-node tree (goal <= 25 ms);
* the same for 1,000 nodes, with the time per node against the 100-node tree (linearity;
  reported, no goal);
* one tick of the loaded 100-node tree against the same tree written by hand in py_trees;
  goal: ratio <= 1.02.

Run::

    .venv/bin/python benchmarks/bench_engine.py
    .venv/bin/python benchmarks/bench_engine.py --runs 50 --process-runs 30
    .venv/bin/python benchmarks/bench_engine.py --process-only --baseline ../main/.venv/bin/sar-tree
"""

from __future__ import annotations

import argparse
import gc
import os
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import py_trees
from sar_plugins.sar.zone_manager import ZoneManager

from sar_framework.engine.api import load_tree
from sar_framework.engine.plugin import Param, leaf
from sar_framework.engine.registry import Registry

Status = py_trees.common.Status
Behaviour = py_trees.behaviour.Behaviour
REPO = Path(__file__).resolve().parent.parent
REFERENCE = REPO / "trees" / "search_and_rescue.yaml"
SAR_TREE = Path(sys.executable).parent / "sar-tree"
ZONES = [{"id": "zone_a", "x": -3.0, "y": 3.0, "yaw": 0.0}]
BASE = {"x": 0.0, "y": 0.0, "yaw": 0.0}


@leaf()
class BenchTick(Behaviour):
    """SUCCESS, every tick."""

    def update(self) -> Status:
        """Succeed."""
        return Status.SUCCESS


@leaf(params=[Param("count", int, default=1, minimum=0), Param("label", str, default="x")])
class BenchParam(Behaviour):
    """A leaf with params."""

    def __init__(self, name: str, *, count: int, label: str) -> None:
        super().__init__(name)
        self.count = count
        self.label = label

    def update(self) -> Status:
        """Succeed."""
        return Status.SUCCESS


@leaf(params=[Param("source", ref="BenchParam")])
class BenchRef(Behaviour):
    """A leaf holding another leaf."""

    def __init__(self, name: str, *, source: Behaviour) -> None:
        super().__init__(name)
        self.source = source

    def update(self) -> Status:
        """Succeed."""
        return Status.SUCCESS


def bench_registry() -> Registry:
    """The three benchmark plugins, nothing else."""
    registry = Registry()
    for cls in (BenchTick, BenchParam, BenchRef):
        registry.add(cls, "benchmarks/bench_engine.py")
    return registry


# -- the synthetic tree ---------------------------------------------------------------------
# A plan node: (kind, attrs, children). Leaves: kind is the plugin name.
Plan = tuple[str, dict[str, Any], list[Any]]


def make_plan(size: int) -> Plan:
    """A tree of exactly ``size`` nodes: groups of 9 under composites, some decorated."""
    count = 1
    groups: list[Plan] = []
    serial = 0
    while count < size:
        serial += 1
        kind = "sequence" if serial % 2 else "selector"
        group: Plan = (kind, {"name": f"Group{serial}", "memory": serial % 2 == 1}, [])
        count += 1
        for i in range(9):
            if count >= size:
                break
            if i == 0:
                leaf_plan: Plan = ("BenchParam", {"id": f"p{serial}", "count": i}, [])
            elif i == 1:
                leaf_plan = ("BenchRef", {"source": f"p{serial}"}, [])
            elif i == 2 and count + 1 < size:
                leaf_plan = ("retry", {"num_failures": 3}, [("BenchTick", {}, [])])
                count += 1
            elif i == 3:
                leaf_plan = ("BenchTick", {"name": f"Check{serial}?"}, [])
            else:
                leaf_plan = ("BenchTick", {}, [])
            group[2].append(leaf_plan)
            count += 1
        groups.append(group)
    return ("sequence", {"name": "Root", "memory": True}, groups)


def plan_yaml(plan: Plan) -> str:
    """The plan as a tree file, in the block style of trees/*.yaml."""
    lines = ["format: 1", "name: bench", "root:"]

    def flow(attrs: dict[str, Any]) -> str:
        return "{" + ", ".join(f"{k}: {v!r}" if isinstance(v, str) and "?" in v else f"{k}: {v}"
                               for k, v in attrs.items()) + "}"

    def emit(node: Plan, indent: str, prefix: str) -> None:
        kind, attrs, children = node
        if kind in ("sequence", "selector"):
            lines.append(f"{indent}{prefix}{kind}:")
            inner = indent + " " * (len(prefix) + 2)
            lines.append(f"{inner}name: {attrs['name']}")
            lines.append(f"{inner}memory: {str(attrs['memory']).lower()}")
            lines.append(f"{inner}children:")
            for child in children:
                emit(child, inner + "  ", "- ")
        elif kind == "retry":
            child_kind = children[0][0]
            lines.append(f"{indent}{prefix}retry: {{num_failures: {attrs['num_failures']}, "
                         f"child: {{{child_kind}: {{}}}}}}")
        else:
            lines.append(f"{indent}{prefix}{kind}: {flow(attrs)}")

    emit(plan, "  ", "")
    return "\n".join(lines) + "\n"


def plan_code(plan: Plan) -> Callable[[], Behaviour]:
    """Straight-line py_trees code for the plan, as a person would write it, compiled."""
    body: list[str] = []
    counter = [0]
    ids: dict[str, str] = {}

    def emit(node: Plan) -> str:
        kind, attrs, children = node
        counter[0] += 1
        var = f"n{counter[0]}"
        if kind in ("sequence", "selector"):
            kids = [emit(c) for c in children]
            cls = "Sequence" if kind == "sequence" else "Selector"
            body.append(f"    {var} = composites.{cls}({attrs['name']!r}, memory="
                        f"{attrs['memory']}, children=[{', '.join(kids)}])")
        elif kind == "retry":
            kid = emit(children[0])
            body.append(f"    {var} = decorators.Retry(name='Retry', child={kid}, "
                        f"num_failures={attrs['num_failures']})")
        elif kind == "BenchParam":
            ids[attrs["id"]] = var
            body.append(f"    {var} = BenchParam(name='BenchParam', count={attrs['count']}, "
                        "label='x')")
        elif kind == "BenchRef":
            body.append(f"    {var} = BenchRef(name='BenchRef', source={ids[attrs['source']]})")
        else:
            body.append(f"    {var} = BenchTick(name={attrs.get('name', 'BenchTick')!r})")
        return var

    root = emit(plan)
    source = "def build():\n" + "\n".join(body) + f"\n    return {root}\n"
    namespace: dict[str, Any] = {
        "composites": py_trees.composites, "decorators": py_trees.decorators,
        "BenchTick": BenchTick, "BenchParam": BenchParam, "BenchRef": BenchRef,
    }
    exec(compile(source, "<hand-built tree>", "exec"), namespace)  # generated code only
    built: Callable[[], Behaviour] = namespace["build"]
    return built


def timed_ms(fn: Callable[[], Any], runs: int, warmup: int = 3) -> tuple[float, float]:
    """Median and minimum wall time of ``fn`` in milliseconds (GC collected between runs)."""
    for _ in range(warmup):
        fn()
    times = []
    for _ in range(runs):
        gc.collect()
        start = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - start)
        del result
    return statistics.median(times) * 1000.0, min(times) * 1000.0


def process_times(runs: int, bytecode: bool,
                  baseline: Path | None = None) -> dict[str, list[float]]:
    """Wall seconds of each whole-process command, the commands alternating run by run.

    Args:
        runs: Runs of each command.
        bytecode: Whether Python may keep compiled modules: True gives every module a
            ``.pyc`` (in a temporary ``PYTHONPYCACHEPREFIX``, written on the warm-up run),
            as a regular install has; False sets ``PYTHONDONTWRITEBYTECODE=1``, so sources
            without a ``.pyc`` (an editable install's) are compiled on every run.
        baseline: Another ``sar-tree`` (say, main's checkout) timed in the same rounds.

    Returns:
        Command label -> its wall times.
    """
    tree = str(REFERENCE)
    commands = {
        "pass": [sys.executable, "-c", "pass"],
        "floor": [sys.executable, "-c", "import yaml, jsonschema"],
        "floor+py_trees": [sys.executable, "-c", "import yaml, jsonschema, py_trees"],
        "floor+engine": [sys.executable, "-c", "import yaml, jsonschema, sar_framework.cli, "
                         "sar_framework.engine.api, sar_framework.engine.registry"],
        "floor+plugins": [sys.executable, "-c", "import importlib, pkgutil, yaml, jsonschema, "
                          "sar_plugins\nfor m in pkgutil.iter_modules(sar_plugins.__path__):\n"
                          "    importlib.import_module('sar_plugins.' + m.name)"],
        "validate": [str(SAR_TREE), "validate", "-q", tree],
    }
    if baseline is not None:
        commands["baseline"] = [str(baseline), "validate", "-q", tree]
    env = dict(os.environ)
    with tempfile.TemporaryDirectory() as cache:
        if bytecode:
            env.pop("PYTHONDONTWRITEBYTECODE", None)
            env["PYTHONPYCACHEPREFIX"] = cache
        else:
            env["PYTHONDONTWRITEBYTECODE"] = "1"

        def wall(argv: list[str]) -> float:
            start = time.perf_counter()
            subprocess.run(argv, check=True, capture_output=True, env=env)
            return time.perf_counter() - start

        for argv in commands.values():
            wall(argv)
        times: dict[str, list[float]] = {label: [] for label in commands}
        for _ in range(runs):
            for label, argv in commands.items():
                times[label].append(wall(argv))
    return times


def ratio_row(
    label: str, times: dict[str, list[float]], key: str, goal: float | None
) -> tuple[str, str, str]:
    """One whole-process row: the median of ``key`` over the median of the floor."""
    ours, floor = statistics.median(times[key]), statistics.median(times["floor"])
    low = min(times[key]) / min(times["floor"])
    return (f"{label} / import yaml, jsonschema",
            f"{ours * 1000:.0f} ms / {floor * 1000:.0f} ms = {ours / floor:.2f}",
            f"{verdict(ours / floor, goal)}; minimums {low:.2f}")


def process_rows(runs: int, baseline: Path | None) -> list[tuple[str, str, str]]:
    """The whole-process rows, without and with compiled bytecode for every module."""
    rows = []
    for bytecode in (False, True):
        times = process_times(runs, bytecode, baseline)
        mode = "with .pyc" if bytecode else "no .pyc"
        rows.append(ratio_row(f"sar-tree validate, reference tree ({mode})", times,
                              "validate", None))
        if baseline is not None:
            rows.append(ratio_row(f"  baseline {baseline} ({mode})", times, "baseline", None))
        rows += [
            ratio_row(f"  import yaml, jsonschema + every built-in plugin module ({mode})", times,
                      "floor+plugins", None),
            ratio_row(f"  python -c 'import yaml, jsonschema, py_trees' ({mode})", times,
                      "floor+py_trees", None),
            ratio_row(f"  import yaml, jsonschema + the engine's and CLI's modules ({mode})",
                      times, "floor+engine", None),
            ratio_row(f"  python -c pass: interpreter and site ({mode})", times, "pass", None),
        ]
    return rows


def tick_ratio(loaded: Behaviour, by_hand: Behaviour, rounds: int) -> tuple[float, float, float]:
    """Per-tick times (ms, median) of two trees and the ratio of their minimums.

    Batches of ticks alternate between the trees so that both share the machine's noise.
    """

    def batch(root: Behaviour) -> float:
        start = time.perf_counter()
        for _ in range(10):
            root.tick_once()
        return (time.perf_counter() - start) / 10

    a, b = [], []
    for _ in range(rounds):
        a.append(batch(loaded))
        b.append(batch(by_hand))
    return statistics.median(a) * 1000.0, statistics.median(b) * 1000.0, min(a) / min(b)


def verdict(value: float, goal: float | None) -> str:
    """``ok`` / ``MISSED`` against a goal (smaller is better), or ``-`` without one."""
    if goal is None:
        return "-"
    return f"{'ok' if value <= goal else 'MISSED'} (goal <= {goal:g})"


def print_table(rows: list[tuple[str, str, str]]) -> None:
    """Print rows of (figure, measured, verdict) as a table."""
    width = max(len(r[0]) for r in rows)
    value_width = max(len(r[1]) for r in rows)
    print(f"{'figure':<{width}}  {'measured':<{value_width}}  verdict")
    print(f"{'-' * width}  {'-' * value_width}  -------")
    for name, value, note in rows:
        print(f"{name:<{width}}  {value:<{value_width}}  {note}")


def run(runs: int, process_runs: int, baseline: Path | None, process_only: bool) -> None:
    """Print the benchmark table."""
    rows = process_rows(process_runs, baseline)
    if process_only:
        print_table(rows)
        return

    def reference() -> Any:
        return load_tree(REFERENCE, context={"zone_manager": ZoneManager(ZONES, BASE)})

    median, low = timed_ms(reference, runs)
    rows.append(("load_tree: reference tree (15 nodes)", f"{median:.2f} ms (min {low:.2f})",
                 verdict(median, 5.0)))
    registry = bench_registry()
    per_node: dict[int, float] = {}
    with tempfile.TemporaryDirectory() as folder:
        loaded_100 = None
        for size, goal in ((100, 25.0), (1000, None)):
            plan = make_plan(size)
            path = Path(folder) / f"tree_{size}.yaml"
            path.write_text(plan_yaml(plan), encoding="utf-8")
            loaded = load_tree(path, registry=registry)
            assert len(loaded.spec) == size
            median, low = timed_ms(lambda p=path: load_tree(p, registry=registry), runs)
            per_node[size] = median / size * 1000.0
            note = verdict(median, goal)
            if size == 1000:
                note = (f"linearity: {per_node[1000]:.1f} us/node vs {per_node[100]:.1f} "
                        f"at 100 nodes (x{per_node[1000] / per_node[100]:.2f})")
            rows.append((f"load_tree: synthetic tree ({size} nodes)",
                         f"{median:.2f} ms (min {low:.2f})", note))
            if size == 100:
                loaded_100 = (loaded.root, plan_code(plan)())
    assert loaded_100 is not None
    tick_loaded, tick_hand, min_ratio = tick_ratio(*loaded_100, rounds=max(runs, 200))
    rows.append(("tick (100 nodes): loaded / by hand",
                 f"{tick_loaded * 1000:.1f} us / {tick_hand * 1000:.1f} us = "
                 f"{tick_loaded / tick_hand:.3f}",
                 verdict(min_ratio, 1.02) + f" on minimums ({min_ratio:.3f})"))
    print_table(rows)


def main() -> None:
    """Parse the options and print the table."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs", type=int, default=30, help="in-process runs per row")
    parser.add_argument("--process-runs", type=int, default=20,
                        help="runs of each command for the whole-process rows")
    parser.add_argument("--baseline", type=Path, default=None,
                        help="another sar-tree (e.g. main's .venv/bin/sar-tree) to time alongside")
    parser.add_argument("--process-only", action="store_true",
                        help="only the whole-process rows")
    args = parser.parse_args()
    run(args.runs, args.process_runs, args.baseline, args.process_only)


if __name__ == "__main__":
    main()
