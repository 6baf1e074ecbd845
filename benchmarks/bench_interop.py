"""Benchmark BT.CPP XML import: py_trees 2.6.0's own XML parser against ``sar-tree import``.

The inputs are read where they are installed or from the ROS overlay, never copied: Nav2's
twelve navigator trees and the BehaviorTree.CPP 4.7.3 example XML of
``decorators/subtree_node.h`` (the overlay ships no other BT.CPP XML: its examples and
tests are not part of the ROS release). Both readers get the same help: a stand-in leaf
class for every leaf tag of the file, with the ports Nav2's palette
(``nav2_tree_nodes.xml``) declares plus the attributes used; ours is
``sar-tree import --scaffold --nodes-model`` followed by validation. The table says, per
file, whether each loads the tree and, if not, its first error, with the median time::

    .venv/bin/python benchmarks/bench_interop.py             # 5 runs per file
    .venv/bin/python benchmarks/bench_interop.py --runs 1
"""

from __future__ import annotations

import argparse
import contextlib
import io
import re
import statistics
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import py_trees
from py_trees.parsers import behaviour_tree_xml
from py_trees.ports import BehaviourWithPorts, PortInformation

from sar_framework.cli import main as sar_tree
from sar_framework.interop.btcpp_file import read_palette
from sar_framework.interop.btcpp_models import guess_type
from sar_framework.interop.mapping import BUILTIN_BY_ID
from sar_framework.interop.xml_source import Element, read_xml

OVERLAY = Path("/work/shared/ros-overlay/src")
NAVIGATORS = OVERLAY / "nav2_bt_navigator" / "behavior_trees"
PALETTE = OVERLAY / "nav2_behavior_tree" / "nav2_tree_nodes.xml"
SUBTREE_HEADER = OVERLAY / "behaviortree_cpp" / "include" / "behaviortree_cpp" / "decorators" \
    / "subtree_node.h"
#: BT.CPP's own leaves (and ``<SubTree>``): no stand-in is made for them.
BTCPP_LEAVES = frozenset({"SubTree", "include", "Script", "ScriptCondition", "SetBlackboard",
                          "UnsetBlackboard", "AlwaysSuccess", "AlwaysFailure", "Sleep",
                          "WasEntryUpdated", "PopFromQueue", "QueueSize"})


def btcpp_example(folder: Path) -> Path:
    """The XML example of BT.CPP's ``subtree_node.h`` comment, as a file in ``folder``."""
    text = SUBTREE_HEADER.read_text()
    found = re.search(r"<root.*?</root>", text, re.DOTALL)
    assert found is not None, f"no XML example in {SUBTREE_HEADER}"
    path = folder / "btcpp_subtree_node_example.xml"
    path.write_text(found.group(0) + "\n")
    return path


def leaf_attributes(element: Element,
                    found: dict[str, dict[str, str]]) -> dict[str, dict[str, str]]:
    """Every user leaf tag below ``element`` (not BT.CPP's own) with an attribute value each."""
    for child in element.children:
        if not child.children and child.tag not in BTCPP_LEAVES \
                and child.tag not in BUILTIN_BY_ID and element.tag != "TreeNodesModel":
            attrs = found.setdefault(child.tag, {})
            for name, value in child.attrs.items():
                if name != "name" and not name.startswith("_"):
                    attrs.setdefault(name, "{x}" if value.startswith("{") else value)
        leaf_attributes(child, found)
    return found


def py_trees_registry(xml: Path) -> dict[str, type]:
    """A stand-in ``BehaviourWithPorts`` class per leaf tag, with palette or used ports.

    Port types: the palette's (a message or unknown type: ``str``, an entry is resolved
    at run time), else guessed from the literal, as our scaffold guesses them.
    """
    models = read_palette(str(PALETTE))[0]
    python = {"str": str, "int": int, "float": float, "bool": bool, "list": list}
    registry: dict[str, type] = {}
    root = read_xml(xml)
    for tag, used in leaf_attributes(root, {}).items():
        model = models.get(tag)
        inputs = {n: PortInformation(data_type=python[guess_type(v)], required=False)
                  for n, v in used.items()}
        outputs: dict[str, PortInformation] = {}
        for port in model.ports if model is not None else ():
            target = outputs if port.direction == "output" else inputs
            inputs.pop(port.name, None)
            target[port.name] = PortInformation(data_type=python.get(port.type, str),
                                                required=False)
        registry[tag] = type(tag, (BehaviourWithPorts,), {
            "INPUT_PORTS": inputs, "OUTPUT_PORTS": outputs,
            "update": lambda self: py_trees.common.Status.FAILURE,
        }, register=False)
    return registry


def load_with_py_trees(xml: Path, scratch: Path) -> str | None:
    """Parse with py_trees' XML parser; None when it loads, else its first error line."""
    try:
        behaviour_tree_xml.parse_behaviour_tree_xml(str(xml), node_registry=py_trees_registry(xml))
    except Exception as exc:  # the benchmark reports whatever it raises
        return f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}"
    return None


def load_with_ours(xml: Path, scratch: Path) -> str | None:
    """``sar-tree import --scaffold --nodes-model`` (it validates); None, or the error."""
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        code = sar_tree(["import", str(xml), "--nodes-model", str(PALETTE), "--scaffold",
                         str(scratch / "leaves"), "-o", str(scratch / f"{xml.stem}.yaml")])
    if code == 0:
        return None
    errors = [line for line in err.getvalue().splitlines() if ": error: " in line]
    first = errors[0].split(": error: ", 1)[1] if errors else err.getvalue().strip()
    return f"{len(errors)} errors; first: {first}"


def measure(load: Callable[[Path, Path], str | None], xml: Path,
            runs: int) -> tuple[str | None, float]:
    """The outcome and the median wall time in ms of ``runs`` loads."""
    times: list[float] = []
    outcome: str | None = None
    for _ in range(runs):
        with tempfile.TemporaryDirectory() as scratch:
            start = time.perf_counter()
            outcome = load(xml, Path(scratch))
            times.append((time.perf_counter() - start) * 1000)
    return outcome, statistics.median(times)


def cell(outcome: str | None, ms: float, width: int) -> str:
    """One table cell: ``ok`` or the error, cut to ``width``."""
    text = f"ok ({ms:.0f} ms)" if outcome is None else f"FAIL: {outcome}"
    return text if len(text) <= width else text[: width - 1] + "…"


def main() -> None:
    """Print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5, help="loads per file (median)")
    parser.add_argument("--width", type=int, default=70, help="width of an error cell")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        files = [*sorted(NAVIGATORS.glob("*.xml")), btcpp_example(Path(folder))]
        name_width = max(len(f.stem) for f in files)
        print(f"{'file':<{name_width}}  {'py_trees 2.6.0 parser':<{args.width}}  sar-tree import")
        totals = [0, 0]
        for xml in files:
            row = []
            for index, load in enumerate((load_with_py_trees, load_with_ours)):
                outcome, ms = measure(load, xml, args.runs)
                totals[index] += outcome is None
                row.append(cell(outcome, ms, args.width))
            print(f"{xml.stem:<{name_width}}  {row[0]:<{args.width}}  {row[1]}")
        print(f"{'loaded':<{name_width}}  {f'{totals[0]} of {len(files)}':<{args.width}}  "
              f"{totals[1]} of {len(files)}")


if __name__ == "__main__":
    main()
