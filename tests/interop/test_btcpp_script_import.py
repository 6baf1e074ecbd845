"""A BT.CPP file with scripts and pre/post conditions, imported, then ticked on both sides.

The door tree (after BT.CPP's pre/post-condition tutorial): ``door_open`` is set by a
``Script``, written by the subtree's ``_onSuccess`` through its remapped port, read by a
``_skipIf`` and a ``ScriptCondition``; ``_onFailure`` writes the root blackboard. The
file is imported with ``--scaffold``, validated, exported, and the export ticked by
BehaviorTree.CPP 4.7.3 and by py_trees with the same scripted leaves.
"""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

from interop.scripted import Script, compare
from sar_framework.cli import main
from sar_framework.engine.registry import discover

pytestmark = pytest.mark.timeout(600)

DOOR = """<root BTCPP_format="4" main_tree_to_execute="MainTree">
  <BehaviorTree ID="MainTree">
    <Sequence>
      <Script code="door_open:=false" />
      <Fallback>
        <Inverter><IsDoorClosed/></Inverter>
        <SubTree ID="DoorClosed" _autoremap="true" door_open="{door_open}"/>
      </Fallback>
      <PassThroughDoor _skipIf="!door_open"/>
      <ScriptCondition code="door_open == true"/>
    </Sequence>
  </BehaviorTree>
  <BehaviorTree ID="DoorClosed">
    <Fallback name="tryOpen" _onSuccess="door_open:=true" _onFailure="@failed := 1">
      <OpenDoor/>
      <RetryUntilSuccessful num_attempts="5"><PickLock/></RetryUntilSuccessful>
      <SmashDoor/>
    </Fallback>
  </BehaviorTree>
</root>
"""

SCRIPTS: list[Script] = [
    {},
    {"IsDoorClosed": ["SUCCESS"], "OpenDoor": ["FAILURE"],
     "PickLock": ["FAILURE", "FAILURE", "SUCCESS"]},
    {"IsDoorClosed": ["SUCCESS"], "OpenDoor": ["FAILURE"], "PickLock": ["FAILURE"],
     "SmashDoor": ["FAILURE"]},
    {"IsDoorClosed": ["SUCCESS"], "OpenDoor": ["RUNNING", "SUCCESS"]},
]


def test_the_door_imports_with_its_scripts(tmp_path: Path,
                                           capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "door.xml").write_text(DOOR)
    tree = tmp_path / "door.yaml"
    assert main(["import", str(tmp_path / "door.xml"), "--scaffold", str(tmp_path / "leaves"),
                 "-o", str(tree)]) == 0, capsys.readouterr().err
    document = yaml.safe_load(tree.read_text())
    inner = document["subtrees"]["DoorClosed"]
    assert inner["ports"] == {"door_open": {"direction": "output", "type": "any"}}
    assert list(inner["root"]["Fallback"]) == ["name", "_onSuccess", "_onFailure", "children"]
    assert document["root"]["Sequence"]["children"][2] == {
        "PassThroughDoor": {"_skipIf": "!door_open"}}
    assert main(["validate", str(tree)]) == 0, capsys.readouterr().err


@pytest.mark.parametrize("script", SCRIPTS, ids=["open", "pick", "smash-fails", "running"])
def test_the_door_ticks_as_btcpp_does(script: Script, tmp_path: Path, btcpp_checker: Path,
                                      capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "door.xml").write_text(DOOR)
    tree = tmp_path / "door.yaml"
    assert main(["import", str(tmp_path / "door.xml"), "--scaffold", str(tmp_path / "leaves"),
                 "-o", str(tree)]) == 0, capsys.readouterr().err
    tree.write_text(tree.read_text().replace("plugins: [leaves/door_leaves.py]\n", ""))
    registry = discover([str(tmp_path / "leaves" / "door_leaves.py")], entry_points=False)
    compare(tree, registry, btcpp_checker, script, halts=True)
