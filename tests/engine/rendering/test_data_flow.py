"""Ports where people see them: ``sar-tree plugins`` and data edges in ``sar-tree render``."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from sar_framework.engine.checking.validate import validate_file
from sar_framework.engine.registry import Registry, discover
from sar_framework.engine.rendering.labels import data_edges
from sar_framework.engine.rendering.render import node_id, render_dot
from sar_framework.plugin_catalogue import plugin_info, port_text

from ..conftest import GENERIC_PLUGINS, REPO, write
from ..port_setup import (
    PORT_PLUGINS,
    port_registry,  # noqa: F401 (pytest fixture)
)

TREE = """
format: 1
root:
  sequence:
    memory: true
    children:
      - Plan: {goal: "{goal}", start: "{here}", path: "{path}"}
      - Follow: {path: "{path}", pose: "{here}"}
      - Emit: {value: "{n}"}
      - Gauge: {value: "{n}"}
blackboard:
  goal: {type: geometry_msgs/msg/Point}
  here: {type: geometry_msgs/msg/Point}
  path: {type: nav_msgs/msg/Path}
  n: {type: int}
"""


def test_catalogue_shows_ports() -> None:
    reg = discover([PORT_PLUGINS], builtins=False, entry_points=False)
    plan = reg.get("Plan")
    assert plan is not None
    assert [port_text(p) for p in plan.ports] == [
        "start: input port geometry_msgs/msg/Point = '{start}'  From here.",
        "goal: input port geometry_msgs/msg/Point (required)  To here.",
        "path: output port nav_msgs/msg/Path  The waypoints, start excluded.",
    ]
    info = plugin_info(plan)
    assert info["ports"][1] == {"name": "goal", "direction": "input",
                                "type": "geometry_msgs/msg/Point", "required": True,
                                "description": "To here."}
    assert info["ports"][0]["default"] == "{start}"


def test_data_edges(tmp_path: Path, registry: Registry) -> None:
    spec = validate_file(write(tmp_path, "tree.yaml", TREE), registry=registry).spec
    assert spec is not None
    # Follow's pose is inout: it writes 'here', which Plan reads
    assert data_edges(spec) == [("0.0", "0.1", "path"), ("0.1", "0.0", "here"),
                                ("0.2", "0.3", "n")]
    source = render_dot(spec, data=True)
    # drawn from the reader with the arrow turned back, so dot keeps the children in order
    line = next(x for x in source.splitlines() if f"{node_id('0.3')} -> {node_id('0.2')}" in x)
    assert "style=dotted" in line and "xlabel=n" in line and "constraint=false" in line
    assert "dir=back" in line
    assert "style=dotted" not in render_dot(spec)


def test_render_cli_data_edges(tmp_path: Path) -> None:
    write(tmp_path, "tree.yaml", TREE)
    run = subprocess.run(
        [sys.executable, "-m", "sar_framework", "render", "tree.yaml", "-o", "tree.dot",
         "--data-edges", "--plugin-path", str(GENERIC_PLUGINS), "--plugin-path",
         str(PORT_PLUGINS)],
        capture_output=True, text=True, cwd=tmp_path, check=False, timeout=120,
        env={"PYTHONPATH": f"{REPO}", "PATH": "/usr/bin:/bin"},
    )
    assert run.returncode == 0, run.stderr
    assert "style=dotted" in (tmp_path / "tree.dot").read_text(encoding="utf-8")


def test_data_edges_include_scripts(tmp_path: Path, registry: Registry) -> None:
    spec = validate_file(write(tmp_path, "tree.yaml", """
        format: 1
        root:
          sequence:
            memory: false
            children:
              - Emit: {value: "{n}"}
              - Script: {code: "m := n + 1"}
              - ScriptCondition: {code: "m > 2"}
    """), registry=registry).spec
    assert spec is not None
    assert data_edges(spec) == [("0.0", "0.1", "n"), ("0.1", "0.2", "m")]
    from sar_framework.engine.rendering.render import render_text

    assert "Script" in render_text(spec) and "digraph" in render_dot(spec, data=True)


def test_labels_show_port_bindings(tmp_path: Path, registry: Registry) -> None:
    from sar_framework.engine.rendering.render import render_text

    spec = validate_file(write(tmp_path, "tree.yaml", """
        format: 1
        blackboard:
          word: {type: str, initial: hi}
          value: {type: int}
        root:
          sequence:
            memory: false
            children:
              - Say: {label: a, text: "{@word}", times: 2, items: "x;y"}
              - Emit: {value: "{=}"}
    """), registry=registry).spec
    assert spec is not None
    assert render_text(spec).splitlines()[1:] == [
        '├── --> Say label="a", text={@word}, times=2, items=["x", "y"]',
        "└── --> Emit value={=}",
    ]
    # the ports left to their defaults show with --all-params, as declared
    assert render_text(spec, all_params=True).splitlines()[2] == (
        "└── --> Emit value={=}, number=7")
    assert "text={@word}" in render_dot(spec)


def test_labels_show_pre_and_post_conditions(tmp_path: Path, registry: Registry) -> None:
    from sar_framework.engine.rendering.render import render_text

    spec = validate_file(write(tmp_path, "tree.yaml", """
        format: 1
        blackboard:
          n: {type: int, initial: 0}
        root:
          sequence:
            memory: false
            _skipIf: "n > 9"
            children:
              - Emit: {value: "{n}", _onSuccess: "n += 1"}
              - Script: {code: "n := 2", _while: "n < 5"}
    """), registry=registry).spec
    assert spec is not None
    assert render_text(spec).splitlines() == [
        '[-] Sequence [sequence, reactive, _skipIf="n > 9"]',
        '├── --> Emit value={n}, _onSuccess="n += 1"',
        '└── --> Script code="n := 2", _while="n < 5"',
    ]


def _laid_out(dot_source: str) -> str:
    """Graphviz's ``-Tplain`` layout of a diagram (skips where dot is not installed)."""
    import shutil

    import pytest

    if shutil.which("dot") is None:
        pytest.skip("Graphviz dot not installed")
    return subprocess.run(["dot", "-Tplain"], input=dot_source, text=True,
                          capture_output=True, check=True).stdout


def test_data_edges_keep_the_children_in_order(tmp_path: Path, registry: Registry) -> None:
    spec = validate_file(write(tmp_path, "tree.yaml", """
        format: 1
        root:
          sequence:
            memory: true
            children:
              - Emit: {value: "{n}", number: 3}
              - sequence:
                  memory: true
                  children:
                    - Emit: {value: "{m}"}
                    - Script: {code: "k := m + n; n := 1"}
    """), registry=registry).spec
    assert spec is not None
    plain = _laid_out(render_dot(spec, data=True))
    x = {line.split()[1]: float(line.split()[2]) for line in plain.splitlines()
         if line.startswith("node ")}
    first, second = node_id("0.1.0"), node_id("0.1.1")
    assert x[node_id("0.0")] < x[node_id("0.1")] and x[first] < x[second], x
    assert "dir=back" in render_dot(spec, data=True)  # the arrow still points at the reader


def _plain_layout(dot_source: str) -> tuple[set[str], list[tuple[str, str]]]:
    """Nodes and edges of the laid-out diagram, as Graphviz's ``-Tplain`` writes them."""
    plain = _laid_out(dot_source)
    nodes = {line.split()[1] for line in plain.splitlines() if line.startswith("node ")}
    edges = [(line.split()[1], line.split()[2]) for line in plain.splitlines()
             if line.startswith("edge ")]
    return nodes, edges


def test_an_entry_many_nodes_share_is_drawn_once(tmp_path: Path, registry: Registry) -> None:
    spec = validate_file(write(tmp_path, "tree.yaml", """
        format: 1
        root:
          sequence:
            memory: true
            children:
              - Emit: {value: "{n}", number: 1}
              - Emit: {value: "{n}", number: 2}
              - Gauge: {value: "{n}"}
              - Gauge: {value: "{n}"}
              - Gauge: {value: "{n}"}
              - Emit: {value: "{k}"}
              - Gauge: {value: "{k}"}
    """), registry=registry).spec
    assert spec is not None
    assert len([e for e in data_edges(spec) if e[2] == "n"]) == 6  # 2 writers x 3 readers
    nodes, edges = _plain_layout(render_dot(spec, data=True))
    assert "entry0" in nodes  # n: one note of its own
    writers, readers = [node_id("0.0"), node_id("0.1")], [node_id(f"0.{i}") for i in (2, 3, 4)]
    assert sorted(t for t, h in edges if h == "entry0") == writers
    assert sorted(h for t, h in edges if t == "entry0") == readers
    assert not any((t in writers and h in readers) or (t in readers and h in writers)
                   for t, h in edges)  # no writer-reader edge of n is left
    # k, shared by two nodes only, keeps its direct, labelled edge
    assert (node_id("0.6"), node_id("0.5")) in edges
    assert "entry1" not in nodes


def test_a_subtree_use_shows_its_port_values(tmp_path: Path, registry: Registry) -> None:
    spec = validate_file(write(tmp_path, "tree.yaml", """
        format: 1
        subtrees:
          Visit:
            ports:
              shelf: {type: str}
              count: {type: int}
            root:
              Emit: {value: "{count}"}
        root:
          sequence:
            memory: true
            children:
              - subtree: {tree: Visit, ports: {shelf: nw, count: "{a}"}}
              - subtree: {tree: Visit, ports: {shelf: se, count: "{b}"}}
        blackboard:
          a: {type: int}
          b: {type: int}
    """), registry=registry).spec
    assert spec is not None
    source = render_dot(spec)
    first = next(x for x in source.splitlines() if x.strip().startswith(node_id("0.0") + " "))
    second = next(x for x in source.splitlines() if x.strip().startswith(node_id("0.1") + " "))
    assert "shelf=nw" in first and "count={a}" in first and "shelf=se" not in first
    assert "shelf=se" in second and "count={b}" in second
    from sar_framework.engine.rendering.render import render_text

    lines = render_text(spec, unicode=False).splitlines()
    assert lines[1].endswith("<<subtree: Visit, shelf=nw, count={a}>>"), lines
    assert lines[2].endswith("<<subtree: Visit, shelf=se, count={b}>>"), lines
