"""Tick a tutorial tree without ROS and print what every leaf did, tick by tick.

Usage (from the repository root)::

    .venv/bin/python trees/tutorials/tick.py trees/tutorials/04_memory_flags.yaml --ticks 4

The tree is loaded with :func:`sar_framework.load_tree`, so it is checked exactly like
``sar-tree validate`` does, with the context object ``zone_manager`` built from
``config/mission_params.yaml`` (four zones, no ROS). After each tick the script prints
the root's status, then every leaf that was ticked, in the order they were ticked::

    tick 1: Root RUNNING
      TakeId    SUCCESS  took survivor_1
      ReportId  RUNNING  reporting survivor_1...

Each line shows the status the leaf returned when it was ticked (a leaf ticked twice in
one tick has two lines). A node that BT.CPP reports SKIPPED shows ``SKIPPED``; a node
whose pre-condition (``_skipIf``, ``_failureIf``...) decided without ticking it has a
line too. ``--set NAME=VALUE`` sets a blackboard entry the caller provides (converted
to the entry's declared type) and ``--entries`` prints the tree's declared entries
(absolute py_trees keys) before the first tick, then those each tick changed::

    tick 2: Mission RUNNING
      DriveA     SUCCESS  at zone_a
      DriveB     RUNNING  driving to zone_b
      /battery: 60.0 -> 35.0
      /visited: 0 -> 1
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import py_trees
import yaml
from sar_plugins.sar.zone_manager import ZoneManager

from sar_framework import load_tree
from sar_framework.engine.api import LoadedTree
from sar_framework.engine.diagnostics import TreeLoadError
from sar_framework.engine.nodes.skipping import was_skipped
from sar_framework.engine.ports import convert, is_message
from sar_framework.engine.scripting import ScriptError
from sar_framework.engine.spec import Category

REPO = Path(__file__).resolve().parents[2]
PARAMS = REPO / "config" / "mission_params.yaml"


def zone_manager_from(path: Path) -> ZoneManager:
    """Build a ZoneManager from a ROS 2 mission parameter file, without ROS.

    Args:
        path: A file laid out like ``config/mission_params.yaml``.

    Returns:
        The zones in ``zone_order`` and the base station.
    """
    params = yaml.safe_load(path.read_text())["/**"]["ros__parameters"]
    zones = [{"id": z, **params["zones"][z]} for z in params["zone_order"]]
    return ZoneManager(zones, params["base_station"])


class Visits(py_trees.visitors.VisitorBase):
    """Every behaviour ticked on the last tick, in order, as it was right after its tick."""

    def __init__(self) -> None:
        super().__init__(full=False)
        self.seen: list[tuple[py_trees.behaviour.Behaviour, str, str]] = []

    def initialise(self) -> None:
        """Forget the previous tick."""
        self.seen = []

    def run(self, behaviour: py_trees.behaviour.Behaviour) -> None:
        """Record the behaviour's status (SKIPPED when it stands for it) and feedback."""
        status = "SKIPPED" if was_skipped(behaviour) else behaviour.status.name
        self.seen.append((behaviour, status, behaviour.feedback_message))


def leaf_rows(visits: Visits, wrappers: set[object]) -> list[tuple[str, str, str]]:
    """Describe the leaves ticked on the last tick.

    Args:
        visits: What the last tick visited.
        wrappers: ids of the behaviours that carry a leaf's pre/post-conditions.

    Returns:
        One ``(name, status, feedback)`` per leaf tick, in the order they were ticked,
        and one per skipped node or condition wrapper that decided without its children.
    """
    ticked = {b.id for b, _, _ in visits.seen}
    rows = []
    for behaviour, status, feedback in visits.seen:
        if behaviour.children:
            if any(child.id in ticked for child in behaviour.children):
                continue
            if status != "SKIPPED" and behaviour.id not in wrappers:
                continue
        rows.append((behaviour.name, status, feedback))
    return rows


def set_entries(loaded: LoadedTree, assignments: list[str]) -> str | None:
    """Write ``NAME=VALUE`` assignments to the tree's declared entries.

    Returns:
        None, or what is wrong with an assignment.
    """
    declared = {entry.name: (key, entry.type) for key, entry in loaded.spec.entries.items()}
    for assignment in assignments:
        name, _, text = assignment.partition("=")
        if name not in declared:
            return f"--set {assignment}: the tree declares no entry '{name}'"
        key, type_ = declared[name]
        try:
            value = text if is_message(type_) else convert(type_, text)
        except ValueError as err:
            return f"--set {assignment}: {err}"
        py_trees.blackboard.Blackboard.set(key, value)
    return None


def entry_values(loaded: LoadedTree) -> dict[str, str]:
    """The tree's declared entries, by absolute key, each value as ``repr`` shows it."""
    storage = py_trees.blackboard.Blackboard.storage
    return {key: repr(storage[key]) if key in storage else "(unset)"
            for key in loaded.spec.entries}


def changes(before: dict[str, str], after: dict[str, str]) -> list[str]:
    """One ``  KEY: OLD -> NEW`` line per entry whose value changed."""
    return [f"  {key}: {before[key]} -> {value}"
            for key, value in after.items() if before[key] != value]


def main(argv: list[str] | None = None) -> int:
    """Load a tree, tick it and print each tick.

    Args:
        argv: Command-line arguments (default: ``sys.argv[1:]``).

    Returns:
        0 when the tree loaded and ticked, 1 when it did not load (the diagnostics go
        to stderr) or a tick stopped on an entry without a value, 2 for a bad ``--set``.
    """
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("tree", help="the tree file")
    parser.add_argument("--ticks", type=int, default=5, help="how many ticks (default 5)")
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                        help="set a declared blackboard entry before the first tick")
    parser.add_argument("--entries", action="store_true",
                        help="print the declared blackboard entries, then each tick's changes")
    args = parser.parse_args(argv)
    try:
        loaded = load_tree(args.tree, context={"zone_manager": zone_manager_from(PARAMS)})
    except TreeLoadError as err:
        sys.stderr.write(f"{err}\n")
        return 1
    problem = set_entries(loaded, args.set)
    if problem:
        sys.stderr.write(f"{problem}\n")
        return 2
    leaves = [n for n in loaded.spec.root.walk() if n.category is Category.LEAF]
    wrappers = {loaded.behaviours[n.uid].id for n in leaves
                if loaded.behaviours[n.uid].children}
    visits = Visits()
    tree = py_trees.trees.BehaviourTree(loaded.root)
    tree.visitors.append(visits)
    tree.setup()
    failed = ""
    values = entry_values(loaded)
    out = ["blackboard before tick 1:", *(f"  {k} = {v}" for k, v in values.items())] \
        if args.entries else []
    ticks: list[tuple[str, list[tuple[str, str, str]], list[str]]] = []
    for number in range(1, args.ticks + 1):
        try:
            tree.tick()
        except (KeyError, ScriptError) as err:  # an entry without a value, as BT.CPP throws
            failed = f"tick {number} stopped: {err.args[0]}"
            break
        head = f"tick {number}: {tree.root.name} {tree.root.status.name}"
        before, values = values, entry_values(loaded)
        ticks.append((head, leaf_rows(visits, wrappers),
                      changes(before, values) if args.entries else []))
    width = max([len(n.name) for n in leaves]
                + [len(name) for _, rows, _ in ticks for name, _, _ in rows])
    for head, rows, changed in ticks:
        out.append(head)
        out.extend(f"  {name:<{width}}  {status:<7}  {feedback}".rstrip()
                   for name, status, feedback in rows)
        out.extend(changed)
    sys.stdout.write("".join(f"{line}\n" for line in out))
    if failed:
        sys.stderr.write(f"{failed}\n")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
