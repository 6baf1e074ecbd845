"""Nav2's navigator trees ticked with scripted leaves, by py_trees and by BehaviorTree.CPP.

Each of the seven navigator trees that import (``test_nav2_navigators.py``) is imported
with ``--scaffold`` and Nav2's palette, exported again, and ticked on both sides with the
same scripted leaf results (the checker registers every scaffolded leaf of the export's
``<TreeNodesModel>`` as a scripted leaf); the transcripts (leaf visits, halts, root status
per tick) must be equal. Ticks are 400 ms apart (the checker sleeps, our side steps its
clock), so the RateControllers (1, 2 and 0.333 Hz) re-tick their planner on the same tick
on both sides.

Nav2's RecoveryNode, PipelineSequence, RoundRobin, RateController and SingleTrigger are
not in BT.CPP: the checker ticks them with stand-ins written from Nav2's documented
behaviour (``btcpp_checker/nav2_standins.h``, no Nav2 code). Our own nodes are checked
against transcripts traced by hand from Nav2's sources in ``test_constructs.py``
(``test_nav2_construct_ticks_as_nav2_source_says``), so the stand-ins are not the only
reference.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from interop.scripted import Script, compare
from interop.test_nav2_navigators import NAVIGATORS, PALETTE, missing_controls
from sar_framework.cli import main
from sar_framework.engine.registry import discover

pytestmark = pytest.mark.timeout(1200)
TICK = 0.4
IMPORTED = [p for p in NAVIGATORS if not missing_controls(p)]

#: name -> script; every script runs on every tree (a leaf the tree lacks is not visited).
SCRIPTS: dict[str, Script] = {
    "all succeed": {},
    "the planner fails once, the controller runs": {
        "ComputePathToPose": ["FAILURE", "SUCCESS"],
        "ComputePathThroughPoses": ["FAILURE", "SUCCESS"],
        "FollowPath": ["RUNNING", "RUNNING", "RUNNING", "SUCCESS"]},
    "the controller fails, the recoveries run": {
        "FollowPath": ["FAILURE", "FAILURE", "RUNNING", "FAILURE", "RUNNING", "SUCCESS"],
        "GoalUpdated": ["FAILURE"], "IsPathValid": ["SUCCESS", "FAILURE", "SUCCESS"],
        "WouldAControllerRecoveryHelp": ["SUCCESS"],
        "ClearLocalCostmap-Subtree": ["FAILURE", "SUCCESS"], "Spin": ["RUNNING", "SUCCESS"],
        "DriveOnHeading": ["SUCCESS", "FAILURE"]},
    "nothing helps": {
        "ComputePathToPose": ["FAILURE"], "ComputePathThroughPoses": ["FAILURE"],
        "FollowPath": ["FAILURE"], "GoalUpdated": ["FAILURE"], "Spin": ["FAILURE"],
        "BtcppWait": ["FAILURE"], "BackUp": ["FAILURE"], "DriveOnHeading": ["FAILURE"],
        "WouldAPlannerRecoveryHelp": ["SUCCESS"]},
}
#: Leaf names only a recovery branch visits (the trees name their clearing actions).
RECOVERY_LEAVES = ("ClearLocalCostmap-Subtree", "ClearGlobalCostmap-Context",
                   "ClearLocalCostmap-Context", "Spin", "BackUp", "BtcppWait")


@pytest.fixture(scope="module")
def imported(tmp_path_factory: pytest.TempPathFactory) -> dict[str, tuple[Path, Path]]:
    """Each navigator imported once: stem -> (tree without plugins:, scaffold module)."""
    found = {}
    for xml in IMPORTED:
        folder = tmp_path_factory.mktemp(xml.stem)
        tree = folder / f"{xml.stem}.yaml"
        assert main(["import", str(xml), "--nodes-model", str(PALETTE), "--scaffold",
                     str(folder / "leaves"), "-o", str(tree)]) == 0
        text = tree.read_text()
        plugins = next(line for line in text.splitlines() if line.startswith("plugins:"))
        tree.write_text(text.replace(plugins + "\n", ""))  # the scripted leaves stand in
        found[xml.stem] = (tree, folder / "leaves" / f"{xml.stem}_leaves.py")
    return found


CASES = [(xml.stem, name) for xml in IMPORTED for name in SCRIPTS]


@pytest.mark.parametrize(("stem", "name"), CASES, ids=[f"{s}-{n}" for s, n in CASES])
def test_navigator_ticks_as_btcpp_does(stem: str, name: str, btcpp_checker: Path,
                                       imported: dict[str, tuple[Path, Path]]) -> None:
    tree, leaves = imported[stem]
    registry = discover([str(leaves)], entry_points=False)
    ours = compare(tree, registry, btcpp_checker, SCRIPTS[name], max_ticks=10,
                   tick_seconds=TICK, halts=True)
    assert any(line.startswith("visit ") for line in ours), ours
    if name == "the controller fails, the recoveries run" and "RoundRobin" in (
            Path(next(p for p in IMPORTED if p.stem == stem)).read_text()):
        assert any(line.split()[1] in RECOVERY_LEAVES for line in ours
                   if line.startswith("visit ")), ours
