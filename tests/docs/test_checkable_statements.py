"""What the docs state that can be checked, checked: clocks, parameter names, node counts.

- docs/reference/mission-contracts.md's clock table names every duration a tree or leaf declares as
  ROS time, and every wall-time one is named ``*_wall_s``;
- no doc line says a ROS-time bound counts wall time;
- every parameter-like name quoted in the docs (```..._s```, ```..._hz```) is a parameter of
  some node or leaf, and a default quoted beside it is its default;
- every ``FILE: ok (N nodes`` a doc shows is what ``sar-tree validate`` counts.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from sar_framework import load_spec
from sar_framework.engine.nodes.node_kinds import KINDS
from sar_framework.engine.registry import default_registry
from sar_framework.leaves import action_params, service_params, topic_params
from sar_framework.orchestrate.inputs import node_parameters

REPO = Path(__file__).resolve().parents[2]
CONTRACTS = REPO / "docs" / "reference" / "mission-contracts.md"
DOCS = sorted([REPO / "README.md", *(REPO / "docs").rglob("*.md")])
ROW = re.compile(r"^\| `([^`]+)`(?: `([^`]+)`)? \| (ROS time|wall) \| (.*) \|$")


def clock_table() -> dict[str, tuple[str, str]]:
    """``name -> (clock, where)`` from the table between the ``clocks`` markers."""
    text = CONTRACTS.read_text()
    body = text[text.index("<!-- clocks -->"):text.index("<!-- /clocks -->")]
    rows = {}
    for line in body.splitlines():
        match = ROW.match(line)
        if match:
            name, attr, clock, where = match.groups()
            rows[f"{name} {attr}" if attr else name] = (clock, where)
    return rows


def leaf_durations() -> dict[str, set[str]]:
    """Every duration a built-in leaf declares: param name -> the leaves declaring it."""
    found: dict[str, set[str]] = {}
    for plugin in default_registry():
        for param in plugin.params:
            if param.name.endswith("_s") or param.name == "duration":
                key = f"{plugin.name} {param.name}" if param.name == "duration" else param.name
                found.setdefault(key, set()).add(plugin.name)
    return found


def all_parameter_names() -> set[str]:
    names = {p.name for table in node_parameters().values() for p in table}
    names |= {p.name for plugin in default_registry() for p in plugin.params}
    toolkit = (*action_params("a"), *service_params("s"), *topic_params("t"))
    names |= {p.name for p in toolkit}  # what the leaf toolkit's bases read
    return names


def test_every_leaf_duration_is_listed_as_ros_time() -> None:
    table = clock_table()
    for name, leaves in leaf_durations().items():
        assert name in table, f"{name} is missing from the clock table"
        clock, where = table[name]
        assert clock == "ROS time", name
        if name.endswith("_s"):
            assert set(re.findall(r"\w+", where)) >= leaves, (name, where)
    assert table["timeout duration"][0] == "ROS time"


def test_every_wall_duration_says_so_in_its_name_and_exists() -> None:
    table = clock_table()
    names = all_parameter_names()
    wall = [name for name, (clock, _) in table.items() if clock == "wall"]
    assert wall
    for name in wall:
        if name.startswith("sar-tree run --"):
            continue  # a command-line option, not a parameter
        assert name.endswith("_wall_s"), name
        calls = [REPO / "sar_framework" / "leaves" / f"{call}.py"
                 for call in ("service_call", "goal_call")]
        assert name in names or any(name in call.read_text() for call in calls), name
    # and every *_wall_s parameter of a node is listed
    for name in names:
        if name.endswith("_wall_s"):
            assert name in table, f"{name} is missing from the clock table"


def test_no_parameter_counts_wall_time_without_saying_so_in_its_name() -> None:
    for table in node_parameters().values():
        for param in table:
            if "wall" in param.description and param.unit == "s":
                assert param.name.endswith("_wall_s"), param.name


def test_no_doc_says_a_ros_time_bound_counts_wall_time() -> None:
    """Regression: tutorial 5 and the BT.CPP interop page said Timeout counts wall-clock time,
    the rules and mission-contracts.md that the leaves' bounds were wall seconds."""
    ros_names = [n for n, (clock, _) in clock_table().items() if clock == "ROS time"
                 and n.endswith("_s")]
    for doc in DOCS:
        for number, line in enumerate(doc.read_text().splitlines(), 1):
            if line.startswith("| `"):
                continue  # the table itself
            said = [n for n in ros_names if f"`{n}`" in line]
            assert not (said and "wall" in line), f"{doc.name}:{number}: {line}"
            assert not re.search(r"timeout\W+\(?`?duration`? in seconds, wall", line), \
                f"{doc.name}:{number}: {line}"
            assert "counts wall-clock time in both" not in line, f"{doc.name}:{number}"


def test_parameter_names_quoted_in_the_docs_exist() -> None:
    """A renamed parameter (nav2_timeout_s -> nav2_timeout_wall_s) leaves no stale name."""
    names = all_parameter_names()
    quoted = re.compile(r"`([a-z][a-z0-9_]*_(?:s|hz))`")
    allowed = {"sim_s", "wall_s", "arrival_sim_s", "arrival_wall_s", "sim_duration_s",
               "wall_duration_s", "sim_start_s", "sim_end_s", "wall_first_tick_s",
               "runner_wall_duration_s", "ticks_per_wall_s", "found_sim_s", "timeout_s",
               "resend_after_wall_s", "ack_timeout_wall_s", "runner_started_s", "nav2_discovered_s",
               "nav2_active_s", "tree_ready_s", "amcl_seeded_s"}  # status.json's startup
    for doc in DOCS:
        for number, line in enumerate(doc.read_text().splitlines(), 1):
            for name in quoted.findall(line):
                assert name in names or name in allowed, f"{doc.name}:{number}: `{name}`"


def test_defaults_quoted_beside_a_parameter_are_its_defaults() -> None:
    defaults = {p.name: p.default for table in node_parameters().values() for p in table}
    defaults |= {p.name: p.default for plugin in default_registry() for p in plugin.params}
    plugged = [spec.kind for spec in default_registry().kind_plugins()]  # Nav2's
    for kind in (*KINDS.values(), *plugged):  # the composites' and decorators' attributes
        defaults |= {a.name: a.default for a in kind.attrs if a.default is not None}
    beside = re.compile(r"`([a-z][a-z0-9_]*)`,? \(?default:? `?(-?[\d.]+)")
    checked = 0
    for doc in DOCS:
        for number, line in enumerate(doc.read_text().splitlines(), 1):
            for name, value in beside.findall(line):
                if name in defaults and isinstance(defaults[name], (int, float)):
                    checked += 1
                    assert float(value.rstrip(".")) == float(defaults[name]), \
                        f"{doc.name}:{number}: {name} default {value}, table {defaults[name]}"
    assert checked >= 5


OK_LINE = re.compile(r"(?:(\S+\.yaml): )?ok \((\d+) nodes")


@pytest.mark.parametrize("doc", DOCS, ids=lambda p: str(p.relative_to(REPO)))
def test_node_counts_in_the_docs_are_what_validate_counts(doc: Path) -> None:
    """Regression: tutorial 8 cited 17 nodes where validate printed 15."""
    for number, line in enumerate(doc.read_text().splitlines(), 1):
        for path, count in OK_LINE.findall(line):
            assert path, f"{doc.name}:{number}: a node count without its file: {line}"
            tree = REPO / path.strip("`(")
            if not tree.is_file():
                continue  # a file made by the tutorial's own commands
            plugins = [REPO / "trees" / "tutorials" / "plugins"]
            spec = load_spec(tree, plugin_paths=[p for p in plugins if p.is_dir()])
            assert len(spec) == int(count), f"{doc.name}:{number}: {path}"
