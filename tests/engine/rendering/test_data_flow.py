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


def test_data_edges_keep_the_children_in_order(tmp_path: Path, registry: Registry) -> None:
    import shutil

    import pytest

    if shutil.which("dot") is None:
        pytest.skip("Graphviz dot not installed")
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
    plain = subprocess.run(["dot", "-Tplain"], input=render_dot(spec, data=True), text=True,
                           capture_output=True, check=True).stdout
    x = {line.split()[1]: float(line.split()[2]) for line in plain.splitlines()
         if line.startswith("node ")}
    first, second = node_id("0.1.0"), node_id("0.1.1")
    assert x[node_id("0.0")] < x[node_id("0.1")] and x[first] < x[second], x
    assert "dir=back" in render_dot(spec, data=True)  # the arrow still points at the reader
