"""Benchmark blackboard ports against references, and load + validate of the reference tree.

Rows (median of the runs, minimum beside it):

* one tick of a tree of producer/consumer pairs passing an int by ports (on py_trees'
  blackboard, through :class:`~sar_framework.engine.building.port_values.PortValues`) against the
  same tree passing it by references (the consumer reads the producer's attribute);
  goal: ratio <= 1.10 on minimums;
* ``load_tree`` of that ports tree (read + validate + resolve + build), for scale;
* ``validate`` of trees/search_and_rescue.yaml (read + schema + semantics, in-process);
  goal <= 5 ms;
* the live entries of the runner's status topic (:mod:`sar_framework.runner.entry_values`)
  for a tree of 10 entries that all change every tick: the changed rows plus their JSON,
  per tick (median), beside the tick itself (goal: <= 100 us a tick, about 1 % of the reference
  mission's 10 ms tick period at speed 20); and for a tree without entries (goal <= 1 us).

Run::

    .venv/bin/python benchmarks/bench_ports.py
    .venv/bin/python benchmarks/bench_ports.py --runs 50 --pairs 50
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import py_trees

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_engine import print_table, tick_ratio, timed_ms, verdict

from sar_framework.engine.api import load_tree, validate
from sar_framework.engine.plugin import Param, leaf
from sar_framework.engine.ports import InputPort, OutputPort
from sar_framework.engine.registry import Registry
from sar_framework.runner.entry_values import EntryTracker, writers_of

Status = py_trees.common.Status
Behaviour = py_trees.behaviour.Behaviour
REPO = Path(__file__).resolve().parent.parent
REFERENCE = REPO / "trees" / "search_and_rescue.yaml"


@leaf(ports=[OutputPort("out", int)])
class PortProducer(Behaviour):
    """Write a counter to its output port each tick."""

    def __init__(self, name: str, *, ports: Any) -> None:
        super().__init__(name)
        self.ports = ports
        self.count = 0

    def update(self) -> Status:
        """Count and write."""
        self.count += 1
        self.ports.set("out", self.count)
        return Status.SUCCESS


@leaf(ports=[InputPort("value", int)])
class PortConsumer(Behaviour):
    """Read its input port each tick."""

    def __init__(self, name: str, *, ports: Any) -> None:
        super().__init__(name)
        self.ports = ports

    def update(self) -> Status:
        """Read."""
        return Status.SUCCESS if self.ports.get("value") > 0 else Status.FAILURE


@leaf()
class RefProducer(Behaviour):
    """Keep a counter in an attribute (what references read)."""

    def __init__(self, name: str) -> None:
        super().__init__(name)
        self.count = 0

    def update(self) -> Status:
        """Count."""
        self.count += 1
        return Status.SUCCESS


@leaf(params=[Param("producer", ref="RefProducer")])
class RefConsumer(Behaviour):
    """Read the referenced producer's counter each tick."""

    def __init__(self, name: str, *, producer: RefProducer) -> None:
        super().__init__(name)
        self.producer = producer

    def update(self) -> Status:
        """Read the producer."""
        return Status.SUCCESS if self.producer.count > 0 else Status.FAILURE


def registry() -> Registry:
    """The four benchmark plugins."""
    reg = Registry()
    for cls in (PortProducer, PortConsumer, RefProducer, RefConsumer):
        reg.add(cls, "benchmarks/bench_ports.py")
    return reg


def tree_yaml(pairs: int, ports: bool) -> str:
    """A sequence of ``pairs`` producer/consumer pairs, by ports or by references."""
    lines = ["format: 1", "root:", "  sequence:", "    memory: false", "    children:"]
    for i in range(pairs):
        if ports:
            lines += [f'      - PortProducer: {{out: "{{v{i}}}"}}',
                      f'      - PortConsumer: {{value: "{{v{i}}}"}}']
        else:
            lines += [f"      - RefProducer: {{id: p{i}}}",
                      f"      - RefConsumer: {{producer: p{i}}}"]
    return "\n".join(lines) + "\n"


def run(runs: int, pairs: int) -> None:
    """Print the benchmark table."""
    rows = []
    reg = registry()
    with tempfile.TemporaryDirectory() as folder:
        by_ports, by_refs = Path(folder) / "ports.yaml", Path(folder) / "refs.yaml"
        by_ports.write_text(tree_yaml(pairs, ports=True), encoding="utf-8")
        by_refs.write_text(tree_yaml(pairs, ports=False), encoding="utf-8")
        median, low = timed_ms(lambda: load_tree(by_ports, registry=reg), runs)
        rows.append((f"load_tree: {2 * pairs} leaves passing data by ports",
                     f"{median:.2f} ms (min {low:.2f})", "-"))
        ports_tree = load_tree(by_ports, registry=reg).root
        refs_tree = load_tree(by_refs, registry=reg).root
    ports_tree.tick_once()
    refs_tree.tick_once()
    assert ports_tree.status is Status.SUCCESS and refs_tree.status is Status.SUCCESS
    tick_ports, tick_refs, min_ratio = tick_ratio(ports_tree, refs_tree, rounds=max(runs, 200))
    rows.append((f"tick ({2 * pairs} leaves): ports / references",
                 f"{tick_ports * 1000:.1f} us / {tick_refs * 1000:.1f} us = "
                 f"{tick_ports / tick_refs:.3f}",
                 verdict(min_ratio, 1.10) + f" on minimums ({min_ratio:.3f})"))
    median, low = timed_ms(lambda: validate(REFERENCE), runs)
    rows.append(("validate: reference tree (load + schema + semantics)",
                 f"{median:.2f} ms (min {low:.2f})", verdict(median, 5.0)))
    rows.extend(entry_rows(reg, runs))
    print_table(rows)


def entry_rows(reg: Registry, runs: int, entries: int = 10) -> list[tuple[str, str, str]]:
    """The per-tick cost of the status topic's entries, with ``entries`` and with none."""
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "entries.yaml"
        path.write_text(tree_yaml(entries, ports=True), encoding="utf-8")
        loaded = load_tree(path, registry=reg)
    assert len(loaded.entries) == entries
    tracker = EntryTracker(loaded.entries, writers_of(loaded.entries.values()))
    root, rounds = loaded.root, max(runs, 200)

    costs, tick_costs = [], []
    for _ in range(rounds):  # time the tick and the entries of each tick apart
        started = time.perf_counter()
        root.tick_once()
        ticked = time.perf_counter()
        json.dumps(tracker.changes(), separators=(",", ":"))
        tick_costs.append(ticked - started)
        costs.append(time.perf_counter() - ticked)
    cost_us, tick_us = statistics.median(costs) * 1e6, statistics.median(tick_costs) * 1e6
    empty = EntryTracker({})
    empty_ms, _ = timed_ms(lambda: [empty.changes() for _ in range(rounds)], 15)
    return [
        (f"live entries: {entries} changing each tick, rows + JSON per tick",
         f"{cost_us:.1f} us (min {min(costs) * 1e6:.1f}; the tick of its {2 * entries} "
         f"leaves {tick_us:.1f} us)", verdict(cost_us, 100.0)),
        ("live entries: a tree without entries, per tick",
         f"{empty_ms * 1000.0 / rounds:.2f} us", verdict(empty_ms * 1000.0 / rounds, 1.0)),
    ]


def main() -> None:
    """Parse the options and print the table."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs", type=int, default=30, help="in-process runs per row")
    parser.add_argument("--pairs", type=int, default=25, help="producer/consumer pairs")
    args = parser.parse_args()
    run(args.runs, args.pairs)


if __name__ == "__main__":
    main()
