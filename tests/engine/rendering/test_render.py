"""Tests for sar_framework.engine.rendering.render: real Graphviz output, real files."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from sar_framework.engine.diagnostics import SourceLocation
from sar_framework.engine.rendering.render import (
    STATUS_COLOURS,
    GraphvizNotFound,
    RenderError,
    node_id,
    render_dot,
    render_text,
    render_to_file,
)
from sar_framework.engine.spec import Category, NodeSpec, TreeSpec

SVG = "{http://www.w3.org/2000/svg}"
COMPOSITES = {"sequence", "selector", "parallel"}
DECORATORS = {
    "one_shot",
    "inverter",
    "retry",
    "repeat",
    "timeout",
    "condition",
    "failure_is_success",
    "success_is_failure",
    "running_is_failure",
}

needs_dot = pytest.mark.skipif(shutil.which("dot") is None, reason="Graphviz dot not installed")


# --------------------------------------------------------------------------- helpers


def node(kind, *children, name=None, id=None, subtree=None, **attrs) -> NodeSpec:
    """A NodeSpec with its uid left blank; `tree()` numbers them."""
    if kind in COMPOSITES:
        category = Category.COMPOSITE
    elif kind in DECORATORS:
        category = Category.DECORATOR
    else:
        category = Category.LEAF
    return NodeSpec(
        kind=kind,
        category=category,
        name=name or kind,
        uid="",
        location=SourceLocation("t.yaml", 1, 1),
        attrs=dict(attrs),
        children=list(children),
        id=id,
        subtree=subtree,
        written=frozenset(attrs),
    )


def ref(source: NodeSpec, param: str, target: NodeSpec) -> None:
    """Make `source` reference `target` through `param`, as the loader does."""
    source.attrs[param] = target.id
    source.refs[param] = target
    source.written |= {param}


def tree(root: NodeSpec, name: str = "test tree", description: str = "") -> TreeSpec:
    """Number uids by child-index path (root "0") and wrap in a TreeSpec."""
    stack = [(root, "0")]
    while stack:
        n, uid = stack.pop()
        n.uid = uid
        stack.extend((c, f"{uid}.{i}") for i, c in enumerate(n.children))
    return TreeSpec(name=name, description=description, root=root, source="t.yaml")


def mission() -> TreeSpec:
    """A small tree using every feature the renderer draws."""
    detect = node("DetectSurvivor", id="det", threshold=0.5, topic="/camera")
    found = node("IsSurvivorDetected", name="Found?")
    ref(found, "detector", detect)
    report = node("ReportSurvivor", id="report", note=None)
    root = node(
        "sequence",
        node(
            "one_shot",
            node("LoadZones", name="Setup", id="setup", file="zones.yaml"),
            name="InitOnce",
            policy="on_completion",
        ),
        node(
            "selector",
            node("retry", node("NavigateToZone", id="nav", zone="A"), name="Retry", num_failures=3),
            node("timeout", detect, name="Limit", duration=5.0),
            found,
            node("failure_is_success", report, name="Optional"),
            name="ZonesRemaining?",
            memory=False,
        ),
        node(
            "parallel",
            node("inverter", node("Battery", name="BatteryOk", low=0.2), name="NotLow"),
            node("repeat", node("Beep"), name="Twice", num_success=2),
            name="Watch",
            policy="success_on_all",
            synchronise=True,
            subtree="watchdog",
        ),
        name="Mission",
        memory=True,
    )
    return tree(root, "mission", "Search & rescue <demo>")


def svg_nodes(path: Path) -> dict[str, ET.Element]:
    """Map Graphviz node id (the SVG <title>) -> the node's <g> element."""
    root = ET.parse(path).getroot()
    out = {}
    for g in root.iter(f"{SVG}g"):
        if g.get("class") == "node":
            out[g.find(f"{SVG}title").text] = g
    return out


def first(element: ET.Element, tag: str) -> ET.Element | None:
    """The first descendant <tag> (shapes sit inside the tooltip's <a>)."""
    return next(element.iter(f"{SVG}{tag}"), None)


def svg_texts(element: ET.Element) -> list[str]:
    return [t.text or "" for t in element.iter(f"{SVG}text")]


def dot_canon(source: str) -> str:
    """Parse DOT with Graphviz itself; fail on any error or warning."""
    proc = subprocess.run(
        ["dot", "-Tcanon"], input=source.encode(), capture_output=True, check=False
    )
    assert proc.returncode == 0, proc.stderr.decode()
    assert proc.stderr == b"", proc.stderr.decode()
    return proc.stdout.decode()


def big_tree(size: int) -> TreeSpec:
    """A wide tree of `size` nodes: sequences of 4, leaves with params and local refs."""
    root = node("sequence", name="Root", memory=True)
    frontier = [root]
    count = 1
    while count < size:
        parent = frontier.pop(0)
        for _ in range(min(4, size - count)):
            if count % 3 == 0:
                child = node("selector", name=f"Sel {count}", memory=False)
                frontier.append(child)
            else:
                child = node("Work", name=f"Work {count}", id=f"w{count}", speed=1.5, zone="A")
                leaves = [c for c in parent.children if c.category is Category.LEAF]
                if leaves and count % 2 == 0:
                    ref(child, "after", leaves[-1])
            parent.children.append(child)
            count += 1
    # A composite needs children: give any empty one a leaf.
    for n in list(root.walk()):
        if n.category is Category.COMPOSITE and not n.children:
            n.children.append(node("Wait"))
    return tree(root, "big")


# --------------------------------------------------------------------------- files


@needs_dot
def test_svg_is_valid_xml_with_every_node_name(tmp_path: Path) -> None:
    spec = mission()
    out = render_to_file(spec, tmp_path / "tree.svg")
    assert out == tmp_path / "tree.svg"
    nodes = svg_nodes(out)
    assert len(nodes) == len(spec)
    for n in spec.nodes():
        g = nodes[node_id(n.uid)]
        assert n.name in svg_texts(g), (n.name, svg_texts(g))
    # The graph title shows the tree name and the escaped description.
    all_text = svg_texts(ET.parse(out).getroot())
    assert "mission" in all_text
    assert "Search & rescue <demo>" in all_text


@needs_dot
def test_png_and_pdf_signatures(tmp_path: Path) -> None:
    png = render_to_file(mission(), tmp_path / "tree.png")
    pdf = render_to_file(mission(), tmp_path / "tree.PDF")
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert png.stat().st_size > 5000
    assert pdf.read_bytes()[:5] == b"%PDF-"
    assert b"%%EOF" in pdf.read_bytes()[-1024:]


@needs_dot
def test_dot_file_has_every_node_and_parses(tmp_path: Path) -> None:
    spec = mission()
    out = render_to_file(spec, tmp_path / "deep" / "er" / "tree.dot")
    source = out.read_text(encoding="utf-8")
    assert source == render_dot(spec)
    canon = dot_canon(source)
    for n in spec.nodes():
        assert re.search(rf"^\s*{node_id(n.uid)}\s*\[", canon, re.M), n.uid
    # One tree edge per child, in child order (ordering=out keeps it on screen).
    tree_edges = re.findall(r"^\s*(\w+) -> (\w+);?$", source, re.M)
    expected = [(node_id(n.uid), node_id(c.uid)) for n in spec.nodes() for c in n.children]
    assert tree_edges == expected
    assert "ordering=out" in source


def test_dot_written_without_graphviz(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("PATH", str(tmp_path / "empty"))
    out = render_to_file(mission(), tmp_path / "tree.dot")
    assert out.read_text(encoding="utf-8").startswith("digraph tree {")


def test_missing_dot_raises_clear_error(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("PATH", str(tmp_path / "empty"))
    with pytest.raises(GraphvizNotFound, match="install Graphviz") as info:
        render_to_file(mission(), tmp_path / "tree.svg")
    assert isinstance(info.value, RuntimeError)
    assert not (tmp_path / "tree.svg").exists()


@pytest.mark.parametrize("name", ["tree.jpg", "tree", "tree.svg.txt", "tree.gv"])
def test_unknown_extension_is_value_error(tmp_path: Path, name: str) -> None:
    with pytest.raises(ValueError, match=r"\.svg, \.png, \.pdf, \.dot"):
        render_to_file(mission(), tmp_path / "sub" / name)
    assert not (tmp_path / "sub").exists()


@needs_dot
def test_dot_failure_is_render_error(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    fake = tmp_path / "bin"
    fake.mkdir()
    (fake / "dot").write_text("#!/bin/sh\necho 'Error: boom' >&2\nexit 3\n")
    (fake / "dot").chmod(0o755)
    monkeypatch.setenv("PATH", str(fake))
    with pytest.raises(RenderError, match="boom"):
        render_to_file(mission(), tmp_path / "tree.svg")


# --------------------------------------------------------------------------- content


@needs_dot
def test_shapes_and_colours_follow_py_trees(tmp_path: Path) -> None:
    spec = mission()
    nodes = svg_nodes(render_to_file(spec, tmp_path / "tree.svg"))
    by_name = {n.name: nodes[node_id(n.uid)] for n in spec.nodes()}

    def polygon_points(g: ET.Element) -> int:
        points = first(g, "polygon").get("points").split()
        return len(points) - 1  # the path is closed: first point repeated

    assert polygon_points(by_name["Mission"]) == 4  # sequence: box
    assert polygon_points(by_name["ZonesRemaining?"]) == 8  # selector: octagon
    assert polygon_points(by_name["Watch"]) == 4  # parallel: parallelogram
    assert first(by_name["Mission"], "polygon").get("fill") == "orange"
    assert first(by_name["ZonesRemaining?"], "polygon").get("fill") == "cyan"
    assert first(by_name["Watch"], "polygon").get("fill") == "gold"
    assert first(by_name["InitOnce"], "ellipse").get("fill") == "ghostwhite"
    assert first(by_name["Setup"], "ellipse").get("fill") == "gray"


def test_memory_policies_and_params_in_labels() -> None:
    source = render_dot(mission())
    for expected in [
        "{-} sequence, memory",
        "[o&#93; selector, reactive",  # "]" is a character reference in HTML labels
        "/_/ parallel, success_on_all, synchronise",
        "-^- one_shot, on_completion",
        "-^- retry, num_failures=3",
        "-^- repeat, num_success=2",
        "-^- timeout, duration=5.0s",
        "-^- inverter",
        "-^- failure_is_success, FAILURE → SUCCESS",
        "id: det",
        "IsSurvivorDetected",
        "threshold=0.5",
        "topic=&quot;/camera&quot;",
        "detector → det",
        "subtree: watchdog",
    ]:
        assert expected in source, expected
    # An unset optional (None) param is left out to keep labels short.
    assert "note=" not in source


@needs_dot
def test_references_are_dashed_labelled_edges(tmp_path: Path) -> None:
    spec = mission()
    nodes = {n.name: n for n in spec.nodes()}
    tail, head = node_id(nodes["Found?"].uid), node_id(nodes["DetectSurvivor"].uid)
    source = render_dot(spec)
    line = next(x for x in source.splitlines() if f"{tail} -> {head}" in x)
    assert "style=dashed" in line and "xlabel=detector" in line and "constraint=false" in line

    root = ET.parse(render_to_file(spec, tmp_path / "tree.svg")).getroot()
    edges = {
        g.find(f"{SVG}title").text: g for g in root.iter(f"{SVG}g") if g.get("class") == "edge"
    }
    edge = edges[f"{tail}->{head}"]
    assert first(edge, "path").get("stroke-dasharray")
    assert "detector" in svg_texts(edge)
    # Tree edges are solid.
    child_edge = edges[f"{node_id(nodes['Mission'].uid)}->{node_id(nodes['InitOnce'].uid)}"]
    assert first(child_edge, "path").get("stroke-dasharray") is None


@needs_dot
def test_subtree_top_node_has_double_border(tmp_path: Path) -> None:
    spec = mission()
    watch = next(n for n in spec.nodes() if n.name == "Watch")
    nodes = svg_nodes(render_to_file(spec, tmp_path / "tree.svg"))
    assert len(list(nodes[node_id(watch.uid)].iter(f"{SVG}polygon"))) == 2
    assert "subtree: watchdog" in svg_texts(nodes[node_id(watch.uid)])
    mission_node = nodes[node_id(spec.root.uid)]
    assert len(list(mission_node.iter(f"{SVG}polygon"))) == 1


@needs_dot
def test_status_colouring_and_legend(tmp_path: Path) -> None:
    spec = mission()
    uids = [n.uid for n in spec.nodes()]
    statuses = {uids[0]: "RUNNING", uids[1]: "SUCCESS", uids[2]: "failure"}
    nodes = svg_nodes(render_to_file(spec, tmp_path / "tree.svg", statuses=statuses))

    def fill(uid: str) -> str:
        shape = first(nodes[node_id(uid)], "polygon")
        if shape is None:
            shape = first(nodes[node_id(uid)], "ellipse")
        return shape.get("fill")

    assert fill(uids[0]) == STATUS_COLOURS["RUNNING"]
    assert fill(uids[1]) == STATUS_COLOURS["SUCCESS"]
    assert fill(uids[2]) == STATUS_COLOURS["FAILURE"]
    # Nodes without a status were never ticked: INVALID.
    assert fill(uids[-1]) == STATUS_COLOURS["INVALID"]
    assert "RUNNING" in svg_texts(nodes[node_id(uids[0])])
    # The legend sits in the graph title, outside the layout.
    root = ET.parse(tmp_path / "tree.svg").getroot()
    graph = next(g for g in root.iter(f"{SVG}g") if g.get("class") == "graph")
    title_texts = [t.text for t in graph.findall(f"{SVG}text")]
    assert {"status:", "SUCCESS", "FAILURE", "RUNNING", "INVALID"} <= set(title_texts)
    legend_fills = {p.get("fill") for p in graph.findall(f"{SVG}polygon")}
    assert set(STATUS_COLOURS.values()) <= legend_fills


def test_no_legend_without_statuses() -> None:
    assert "status:" not in render_dot(mission())
    coloured = render_dot(mission(), statuses={})
    assert "status:" in coloured
    # An empty map still colours: every node INVALID (never ticked).
    assert coloured.count(f'fillcolor="{STATUS_COLOURS["INVALID"]}"') == len(mission())


def test_py_trees_status_members_accepted_and_bad_status_rejected() -> None:
    py_trees = pytest.importorskip("py_trees")
    source = render_dot(mission(), statuses={"0": py_trees.common.Status.SUCCESS})
    assert STATUS_COLOURS["SUCCESS"] in source
    with pytest.raises(ValueError, match="unknown status 'DONE'"):
        render_dot(mission(), statuses={"0": "DONE"})


@needs_dot
@pytest.mark.parametrize(
    "name",
    [
        "ZonesRemaining?",
        'Say "hi" & <wave>',
        "back\\slash \\N \\l",
        "<b>not html</b>",
        "tab\tand\nnewline",
        "Zoné ✓ 救援",
        "]]> &amp; -- ' ;",
        "]",  # regression: Graphviz 2.43 rejected a bare "]" right before </B>
        "Check[zone]",
    ],
)
def test_special_characters_in_names(tmp_path: Path, name: str) -> None:
    leaf = node("Probe", name=name, id=name, msg=name)
    spec = tree(node("sequence", leaf, name=name, memory=True), name=name, description=name)
    dot_canon(render_dot(spec))
    nodes = svg_nodes(render_to_file(spec, tmp_path / "tree.svg"))
    shown = " ".join(name.split("\t")).replace("\n", " ")
    for n in spec.nodes():
        assert shown in svg_texts(nodes[node_id(n.uid)])


@needs_dot
@settings(
    max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(name=st.text(min_size=1, max_size=30))
def test_any_name_renders(tmp_path: Path, name: str) -> None:
    spec = tree(node("selector", node("Probe", name=name, id="p", v=name), name=name, memory=False))
    out = render_to_file(spec, tmp_path / "any.svg")
    texts = " ".join(svg_texts(ET.parse(out).getroot()))
    visible = re.sub(r"[\x00-\x1f\x7f]", " ", name).strip()
    for word in visible.split():
        assert word in texts


def test_node_ids_stable_unique_and_from_uid() -> None:
    assert node_id("0") == "n0"
    assert node_id("0.1.3") == "n0_1_3"
    odd = ["0_1", "0-1", "a", 'x"y', "0..1", ""]
    ids = [node_id(u) for u in ["0.1", *odd]]
    assert len(set(ids)) == len(ids)
    assert all(re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", i) for i in ids)
    assert render_dot(mission()) == render_dot(mission())


def test_duplicate_uids_rejected() -> None:
    spec = mission()
    spec.root.children[1].uid = spec.root.children[0].uid
    with pytest.raises(ValueError, match="duplicate uid"):
        render_dot(spec)


# --------------------------------------------------------------------------- text


def test_unicode_text_tree_exact() -> None:
    assert render_text(mission()) == (
        "{-} Mission [sequence, memory]\n"
        "├── -^- InitOnce [one_shot, on_completion]\n"
        '│   └── --> Setup [LoadZones, id=setup] file="zones.yaml"\n'
        "├── [o] ZonesRemaining? [selector, reactive]\n"
        "│   ├── -^- Retry [retry, num_failures=3]\n"
        '│   │   └── --> NavigateToZone [id=nav] zone="A"\n'
        "│   ├── -^- Limit [timeout, duration=5.0s]\n"
        '│   │   └── --> DetectSurvivor [id=det] threshold=0.5, topic="/camera"\n'
        "│   ├── --> Found? [IsSurvivorDetected] detector → det\n"
        "│   └── -^- Optional [failure_is_success, FAILURE → SUCCESS]\n"
        "│       └── --> ReportSurvivor [id=report]\n"
        "└── /_/ Watch [parallel, success_on_all, synchronise] «subtree: watchdog»\n"
        "    ├── -^- NotLow [inverter]\n"
        "    │   └── --> BatteryOk [Battery] low=0.2\n"
        "    └── -^- Twice [repeat, num_success=2]\n"
        "        └── --> Beep\n"
    )


def test_ascii_text_tree_is_pure_ascii() -> None:
    spec = mission()
    spec.root.children[0].name = "Init ✓ Zoné"
    text = render_text(spec, unicode=False)
    assert text.isascii()
    lines = text.splitlines()
    assert lines[0] == "{-} Mission [sequence, memory]"
    assert lines[1] == "|-- -^- Init \\u2713 Zon\\xe9 [one_shot, on_completion]"
    assert "|   `-- --> Setup" in lines[2]
    assert "detector -> det" in text
    assert "FAILURE -> SUCCESS" in text
    assert "`-- /_/ Watch [parallel, success_on_all, synchronise] <<subtree: watchdog>>" in text
    assert len(lines) == len(spec)


def test_unicode_text_has_tree_glyphs_and_one_line_per_node() -> None:
    spec = mission()
    spec.root.name = "two\nlines"
    text = render_text(spec)
    assert {"├── ", "└── ", "│   "} <= {g for g in ("├── ", "└── ", "│   ") if g in text}
    assert text.splitlines()[0] == "{-} two lines [sequence, memory]"
    assert len(text.splitlines()) == len(spec)


def test_long_values_truncated() -> None:
    spec = tree(node("Say", text="x" * 200, items=[1, 2, 3]))
    line = render_text(spec, unicode=False)
    assert '"xxxxxxxx' in line and "..." in line and "x" * 60 not in line
    assert "items=[1, 2, 3]" in line
    assert "x" * 60 not in render_dot(spec)


def test_many_params_capped_in_diagram() -> None:
    spec = tree(node("Many", **{f"p{i}": i for i in range(20)}))
    source = render_dot(spec)
    assert "p0=0" in source and "p6=6" in source and "p7=7" not in source
    assert "… 13 more" in source
    # The terminal view shows them all.
    assert "p19=19" in render_text(spec)


def test_deep_tree_needs_no_recursion() -> None:
    leaf = node("Leaf")
    top = leaf
    for _ in range(sys.getrecursionlimit() + 100):
        top = node("inverter", top)
    spec = tree(top)
    assert len(render_text(spec).splitlines()) == len(spec)
    assert render_dot(spec).count(" -> ") == len(spec) - 1


# --------------------------------------------------------------------------- size
# (how fast is measured in benchmarks/bench_render.py, never in a test)


@needs_dot
def test_thousand_node_tree_renders_every_node_to_svg(tmp_path: Path) -> None:
    spec = big_tree(1000)
    assert len(spec) >= 1000
    out = render_to_file(spec, tmp_path / "big.svg")
    assert len(svg_nodes(out)) == len(spec)
