"""``tree.svg`` and ``status.json`` show what ``events.jsonl`` says, under ``sar-tree run``.

Two missions, each run to its end (the runner exits on completion): the reference tree,
written with py_trees' kinds, and a patrol written with BehaviorTree.CPP's
(``btcpp_kinds_patrol.yaml``: SequenceWithMemory, ForceSuccess, Repeat, Script,
ScriptCondition, Nav2's NavigateToPose), whose nodes reset finished children to BT.CPP's
IDLE. For every leaf, the status in ``status.json`` is its last ``status`` event's; for
every node, ``tree.svg`` is filled with the colour of its status in ``status.json``; and
py_trees_ros never failed to find the tree's tip (it says so only in the runner's log,
and then publishes no snapshot).

The reference tree's run is ``test_log_wording``'s ordinary run (its report server refuses
every report, so NotifyBase fails too): its tests call the checks below on it, one mission
fewer.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import pytest

from sar_framework.engine.api import load_spec
from sar_framework.engine.rendering.render import STATUS_COLOURS, node_id
from sar_framework.engine.spec import Category

from .helpers import FAST, no_traceback, read_json, read_jsonl, run_to_end

pytestmark = [pytest.mark.slow, pytest.mark.ros]

BTCPP_TREE = Path(__file__).resolve().parent / "btcpp_kinds_patrol.yaml"
#: py_trees_ros's words when the root has no tip (trees.py); no event or status says it.
TIP_ERROR = "the root behaviour failed to return a tip"
SVG = "{http://www.w3.org/2000/svg}"
#: Outer safety bound (wall seconds) on a whole mission; each ends on its own completion.
MISSION_OUTER_S = 180.0


@pytest.fixture(scope="module")
def mission(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    """The BT.CPP patrol, run to its end; it calls no detect or report server."""
    folder = tmp_path_factory.mktemp(BTCPP_TREE.stem) / "report"
    code, out = run_to_end([str(BTCPP_TREE), "--speed", FAST, "--no-detect-server",
                            "--no-report-server"], folder, timeout=MISSION_OUTER_S)
    return {"tree": BTCPP_TREE, "code": code, "out": out, "report": folder}


def last_said(report: Path) -> dict[str, str]:
    """Each node's last ``status`` event's status, by uid."""
    said: dict[str, str] = {}
    for event in read_jsonl(report / "events.jsonl"):
        if event["kind"] == "status":
            said[event["node_uid"]] = event["status"]
    return said


def svg_fills(svg: Path) -> dict[str, str]:
    """Each drawn node's fill colour, by Graphviz node id."""
    fills = {}
    for group in ET.parse(svg).getroot().iter(f"{SVG}g"):
        if group.get("class") != "node":
            continue
        title = group.find(f"{SVG}title")
        shape = next(e for e in group.iter() if e.get("fill") not in (None, "none"))
        assert title is not None and title.text is not None
        fills[title.text] = shape.get("fill", "")
    return fills


def check_completes_without_a_tip_error(mission: dict[str, Any]) -> None:
    """The run ended once, complete, and py_trees_ros always found the tree's tip.

    Args:
        mission: ``tree``, exit ``code``, printed ``out`` and ``report`` folder of a run.
    """
    out = mission["out"]
    assert mission["code"] == 0, out
    assert out.count("Mission complete.") == 1 and no_traceback(out), out
    runner_log = (mission["report"] / "runner.log").read_text(encoding="utf-8")
    assert "Mission complete." in runner_log
    assert TIP_ERROR not in runner_log, runner_log


def check_views_agree_with_the_events(mission: dict[str, Any]) -> None:
    """Each leaf's status in status.json is its last event's; tree.svg is coloured by it.

    Args:
        mission: ``tree``, exit ``code``, printed ``out`` and ``report`` folder of a run.
    """
    assert mission["code"] == 0, mission["out"]
    spec = load_spec(mission["tree"])
    said = last_said(mission["report"])
    nodes = read_json(mission["report"] / "status.json")["nodes"]
    leaves = [node.uid for node in spec.nodes() if node.category == Category.LEAF]
    assert said and set(said) <= set(leaves)
    assert {uid: nodes.get(uid) for uid in leaves} == {uid: said.get(uid) for uid in leaves}
    fills = svg_fills(mission["report"] / "tree.svg")
    assert {node.uid: fills[node_id(node.uid)] for node in spec.nodes()} == \
        {node.uid: STATUS_COLOURS[nodes.get(node.uid, "INVALID")] for node in spec.nodes()}


def test_the_mission_completes_without_a_tip_error(mission: dict[str, Any]) -> None:
    check_completes_without_a_tip_error(mission)


def test_status_json_and_tree_svg_agree_with_the_events(mission: dict[str, Any]) -> None:
    check_views_agree_with_the_events(mission)


def test_the_btcpp_patrol_shows_how_it_ended(mission: dict[str, Any]) -> None:
    spec = load_spec(BTCPP_TREE)
    nodes = read_json(mission["report"] / "status.json")["nodes"]
    by_name = {node.name: nodes.get(node.uid) for node in spec.nodes()}
    # the check that ended the loop failed; the drive and the count that ran succeeded
    assert by_name["RoundLeft?"] == "FAILURE" and by_name["Round"] == "FAILURE"
    assert by_name["NavigateToPose"] == by_name["CountRound"] == "SUCCESS"
    assert by_name["UntilNoRoundLeft"] == by_name["TwoRounds?"] == by_name["Patrol"] == \
        "SUCCESS"
    counted = [e for e in read_jsonl(mission["report"] / "events.jsonl")
               if e["kind"] == "status" and e["node_name"] == "CountRound"]
    assert len(counted) == 2, counted
