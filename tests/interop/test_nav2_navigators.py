"""Nav2's twelve navigator trees, end to end: import, validate, render, export, BT.CPP loads.

The trees and the palette are read where ROS installs them (``share/`` under
``$AMENT_PREFIX_PATH``) or from the ROS overlay's sources; they are never copied here.
Each file is imported with ``--scaffold`` and ``--nodes-model nav2_tree_nodes.xml``
(their ports): every Nav2 leaf is one of ``sar_plugins.nav2`` and every control and
decorator one of our kinds, so nothing is scaffolded. The tree file is validated, drawn
as SVG with graphviz, exported back to BT.CPP XML, and the real BehaviorTree.CPP 4.7.3
(the checker, ``MAX_TICKS`` 0) loads the export: every check ``createTreeFromText`` makes.
"""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest
import yaml
from py_trees.common import Status

from sar_framework.cli import main
from sar_framework.engine.api import load_tree
from sar_framework.interop.xml_source import Element
from sar_framework.testing.nav2_navigators import nav2_share, navigator_trees

pytestmark = pytest.mark.timeout(1200)
NAVIGATORS = list(navigator_trees().values())
PALETTE = nav2_share("nav2_behavior_tree", "nav2_tree_nodes.xml")


def tags(element: Element) -> set[str]:
    """Every element name below ``element``."""
    found = {element.tag}
    for child in element.children:
        found |= tags(child)
    return found


def test_all_twelve_navigator_trees_are_found() -> None:
    assert len(NAVIGATORS) == 12, NAVIGATORS
    assert PALETTE.is_file()


@pytest.mark.parametrize("xml", NAVIGATORS, ids=[p.stem for p in NAVIGATORS])
def test_navigator_imports_validates_renders_and_exports_to_what_btcpp_loads(
        xml: Path, tmp_path: Path, btcpp_checker: Path,
        capsys: pytest.CaptureFixture[str]) -> None:
    tree = tmp_path / f"{xml.stem}.yaml"
    assert main(["import", str(xml), "--nodes-model", str(PALETTE), "--scaffold",
                 str(tmp_path / "leaves"), "-o", str(tree)]) == 0, capsys.readouterr().err
    assert "plugins:" not in tree.read_text()  # every Nav2 leaf is one of sar_plugins.nav2
    assert main(["validate", str(tree)]) == 0, capsys.readouterr().err
    svg = tmp_path / f"{xml.stem}.svg"
    assert main(["render", str(tree), "-o", str(svg)]) == 0, capsys.readouterr().err
    assert svg.read_text().lstrip().startswith(("<?xml", "<svg"))
    exported = tmp_path / f"{xml.stem}.xml"
    assert main(["export", str(tree), "-o", str(exported)]) == 0, capsys.readouterr().err
    script = tmp_path / "none.script"
    done = subprocess.run([str(btcpp_checker), str(exported), str(script), "0"],
                          capture_output=True, text=True, timeout=60, check=False)
    assert done.returncode == 0, f"BT.CPP refused the export:\n{done.stderr}"
    assert done.stdout.startswith("models ")


DOCK_XML = ('<root><BehaviorTree ID="t"><Sequence>\n<DockRobot dock_id="d1" '
            'max_staging_time="2.0"/></Sequence></BehaviorTree></root>')


def test_a_scaffold_takes_its_ports_from_the_palette(tmp_path: Path) -> None:
    xml = tmp_path / "dock.xml"  # DockRobot: a palette leaf sar_plugins.nav2 does not provide
    xml.write_text(DOCK_XML)
    tree = tmp_path / "dock.yaml"
    assert main(["import", str(xml), "--nodes-model", str(PALETTE), "--scaffold",
                 str(tmp_path / "leaves"), "-o", str(tree)]) == 0
    leaves = (tmp_path / "leaves" / "dock_leaves.py").read_text()
    assert "class DockRobot(py_trees.behaviour.Behaviour):" in leaves
    assert "InputPort('max_staging_time', float, default=1000.0" in leaves
    assert "# InputPort('server_name', str" in leaves  # BT.CPP-optional, never set


def test_nav2_wait_imports_as_nav2_wait(tmp_path: Path,
                                       capsys: pytest.CaptureFixture[str]) -> None:
    """Before: our dwell was 'Wait', so Nav2's <Wait> was scaffolded as 'BtcppWait'."""
    xml = tmp_path / "wait.xml"
    xml.write_text('<root><BehaviorTree ID="t"><Wait wait_duration="5.0"/></BehaviorTree>'
                   '</root>')
    tree = tmp_path / "wait.yaml"
    assert main(["import", str(xml), "--nodes-model", str(PALETTE), "--scaffold",
                 str(tmp_path / "leaves"), "-o", str(tree)]) == 0
    err = capsys.readouterr().err
    assert "warning" not in err and "Btcpp" not in err
    text = tree.read_text()
    assert "Wait: {wait_duration: 5.0}" in text and "plugins:" not in text
    spec = load_tree(tree, {}).spec
    assert spec.root.kind == "Wait" and spec.root.ports["wait_duration"] == 5.0


def test_scaffolded_leaves_build_and_fail_saying_they_are_not_written(tmp_path: Path) -> None:
    xml = tmp_path / "dock.xml"
    xml.write_text(DOCK_XML)
    tree = tmp_path / "dock.yaml"
    assert main(["import", str(xml), "--nodes-model", str(PALETTE), "--scaffold",
                 str(tmp_path / "leaves"), "-o", str(tree)]) == 0
    loaded = load_tree(tree, {})
    loaded.root.tick_once()
    assert loaded.root.status == Status.FAILURE
    first = next(b for b in loaded.root.iterate() if b.name == "DockRobot")
    # (its status is reset to INVALID: BT.CPP's Sequence resets its children when it ends)
    assert first.feedback_message == ("DockRobot is scaffolded: its behaviour is not "
                                      "written yet")
    assert first.ports.get("max_staging_time") == 2.0  # type: ignore[attr-defined]


@pytest.mark.parametrize(("stem", "entry", "kind", "text"), [
    ("navigate_to_pose_w_replanning_and_recovery", "goal", "geometry_msgs/msg/PoseStamped",
     "Set by the caller: nothing in navigate_to_pose_w_replanning_and_recovery.xml writes "
     "it; read by <ComputePathToPose> port 'goal'."),
    ("navigate_through_poses_w_replanning_and_recovery", "goals", "list",
     "Set by the caller (written by <RemovePassedGoals> port 'output_goals', after it is "
     "read); read by <RemovePassedGoals> port 'input_goals', <ComputePathThroughPoses> port "
     "'goals'."),
])
def test_the_goals_nav2_sets_become_declared_inputs(stem: str, entry: str, kind: str,
                                                     text: str, tmp_path: Path) -> None:
    xml = next(p for p in NAVIGATORS if p.stem == stem)
    tree = tmp_path / "nav.yaml"
    assert main(["import", str(xml), "--nodes-model", str(PALETTE), "--scaffold",
                 str(tmp_path / "leaves"), "-o", str(tree)]) == 0
    blackboard = yaml.safe_load(tree.read_text())["blackboard"]
    assert blackboard[entry] == {"type": kind, "description": text}
    callers = [name for name, decl in blackboard.items()
               if decl["description"].startswith("Set by the caller")]
    assert callers == [entry]  # {path} is written by ComputePathToPose: not an input


def shape(node: object) -> list[tuple]:
    """Pre-order (kind, name, attrs, ports as written) of a spec, minus server_timeout."""
    found = [(node.kind, node.name, sorted((k, str(v)) for k, v in node.attrs.items()
                                           if k in node.written),
              sorted((k, str(v)) for k, v in node.ports.items() if k != "server_timeout"))]
    for child in node.children:
        found += shape(child)
    return found


def test_the_nav2_example_mission_holds_the_default_navigator_node_for_node(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """trees/examples/search_and_rescue_nav2.yaml's NavigateWithRecovery is Nav2's
    navigate_to_pose_w_replanning_and_recovery.xml as imported (server_timeout aside)."""
    from sar_framework.engine.api import validate

    xml = next(p for p in NAVIGATORS if p.name == "navigate_to_pose_w_replanning_and_recovery.xml")
    imported = tmp_path / "navigator.yaml"
    assert main(["import", str(xml), "--nodes-model", str(PALETTE), "-o", str(imported)]) == 0, \
        capsys.readouterr().err
    upstream = validate(imported).spec
    example = validate(Path(__file__).resolve().parents[2] / "trees" / "examples"
                       / "search_and_rescue_nav2.yaml").spec
    assert upstream is not None and example is not None
    inserted = next(n for n in example.nodes() if n.subtree == "NavigateWithRecovery")
    assert shape(inserted) == shape(upstream.root)
