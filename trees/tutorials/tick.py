"""Tick a tutorial tree without ROS and print what every leaf did, tick by tick.

Usage (from the repository root)::

    .venv/bin/python trees/tutorials/tick.py trees/tutorials/03_memory_flags.yaml --ticks 4

The tree is loaded with :func:`sar_framework.load_tree`, so it is checked exactly like
``sar-tree validate`` does, with the context object ``zone_manager`` built from
``config/mission_params.yaml`` (four zones, no ROS). After each tick the script prints
the root's status, then every leaf that was ticked, in tree order::

    tick 1: Root RUNNING
      TakeId    SUCCESS  took survivor_1
      ReportId  RUNNING  reporting survivor_1...
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import py_trees
import yaml

from sar_framework import load_tree
from sar_framework.engine.diagnostics import TreeLoadError
from sar_framework.mission.zone_manager import ZoneManager

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


def leaf_lines(root: py_trees.behaviour.Behaviour, visited: set[object]) -> list[str]:
    """Describe the leaves ticked on the last tick.

    Args:
        root: The tree's root.
        visited: ids of the behaviours ticked on the last tick.

    Returns:
        One ``name  STATUS  feedback`` line per ticked leaf, in tree order.
    """
    leaves = [b for b in root.iterate() if not b.children]
    width = max(len(b.name) for b in leaves)
    leaves = [b for b in leaves if b.id in visited]
    return [f"  {b.name:<{width}}  {b.status.name:<7}  {b.feedback_message}".rstrip()
            for b in leaves]


def main(argv: list[str] | None = None) -> int:
    """Load a tree, tick it and print each tick.

    Args:
        argv: Command-line arguments (default: ``sys.argv[1:]``).

    Returns:
        0 when the tree loaded, 1 when it did not (the diagnostics go to stderr).
    """
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("tree", help="the tree file")
    parser.add_argument("--ticks", type=int, default=5, help="how many ticks (default 5)")
    args = parser.parse_args(argv)
    try:
        loaded = load_tree(args.tree, context={"zone_manager": zone_manager_from(PARAMS)})
    except TreeLoadError as err:
        sys.stderr.write(f"{err}\n")
        return 1
    snapshot = py_trees.visitors.SnapshotVisitor()
    tree = py_trees.trees.BehaviourTree(loaded.root)
    tree.visitors.append(snapshot)
    tree.setup()
    out: list[str] = []
    for number in range(1, args.ticks + 1):
        tree.tick()
        out.append(f"tick {number}: {tree.root.name} {tree.root.status.name}")
        out.extend(leaf_lines(tree.root, set(snapshot.visited)))
    sys.stdout.write("\n".join(out) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
