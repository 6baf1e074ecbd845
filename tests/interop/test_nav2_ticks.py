"""Nav2's navigator trees ticked with scripted leaves, by py_trees and by BehaviorTree.CPP.

Each of the seven navigator trees whose Nav2 nodes the checker has stand-ins for is
imported with Nav2's palette (its leaves are ``sar_plugins.nav2``'s), exported again, and
ticked on both sides with the same scripted leaf results (here every leaf of the registry
is replaced by a scripted one of the same name and ports; the checker registers every
leaf of the export's ``<TreeNodesModel>`` as a scripted leaf); the transcripts (leaf
visits, halts, root status per tick) must be equal. Ticks are 400 ms apart (the checker
sleeps, our side steps its clock), so the RateControllers (1, 2 and 0.333 Hz) re-tick
their planner on the same tick on both sides.

Nav2's RecoveryNode, PipelineSequence, RoundRobin, RateController and SingleTrigger are
not in BT.CPP: the checker ticks them with stand-ins written from Nav2's documented
behaviour (``btcpp_checker/nav2_standins.h``, no Nav2 code). It has none for Nav2's
GoalUpdatedController, PathLongerOnApproach, DistanceController, SpeedController and
GoalUpdater, so the five navigators that use them are left out here (their kinds are
checked in ``tests/engine/test_nav2_goal_decorators.py`` and
``test_nav2_robot_decorators.py``). Our own nodes are checked
against transcripts traced by hand from Nav2's sources in ``test_constructs.py``
(``test_nav2_construct_ticks_as_nav2_source_says``), so the stand-ins are not the only
reference.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from interop.scripted import Script, compare
from interop.test_nav2_navigators import NAVIGATORS, PALETTE, tags
from sar_framework.cli import main
from sar_framework.engine.registry import discover
from sar_framework.interop.xml_source import read_xml

pytestmark = pytest.mark.timeout(1200)
TICK = 0.4
#: Nav2's nodes the checker has no stand-in for (``btcpp_checker/nav2_standins.h``).
NO_STANDIN = {"GoalUpdatedController", "PathLongerOnApproach", "DistanceController",
              "SpeedController", "GoalUpdater"}
IMPORTED = [p for p in NAVIGATORS if not tags(read_xml(p)) & NO_STANDIN]

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
        "Wait": ["FAILURE"], "BackUp": ["FAILURE"], "DriveOnHeading": ["FAILURE"],
        "WouldAPlannerRecoveryHelp": ["SUCCESS"]},
}
#: Leaf names only a recovery branch visits (the trees name their clearing actions).
RECOVERY_LEAVES = ("ClearLocalCostmap-Subtree", "ClearGlobalCostmap-Context",
                   "ClearLocalCostmap-Context", "Spin", "BackUp", "Wait")


@pytest.fixture(scope="module")
def imported(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """Each navigator imported once: stem -> its tree file (no plugins: every leaf is Nav2's)."""
    found = {}
    for xml in IMPORTED:
        tree = tmp_path_factory.mktemp(xml.stem) / f"{xml.stem}.yaml"
        assert main(["import", str(xml), "--nodes-model", str(PALETTE), "-o", str(tree)]) == 0
        assert "plugins:" not in tree.read_text()
        found[xml.stem] = tree
    return found


CASES = [(xml.stem, name) for xml in IMPORTED for name in SCRIPTS]


@pytest.mark.parametrize(("stem", "name"), CASES, ids=[f"{s}-{n}" for s, n in CASES])
def test_navigator_ticks_as_btcpp_does(stem: str, name: str, btcpp_checker: Path,
                                       imported: dict[str, Path]) -> None:
    tree = imported[stem]
    registry = discover(entry_points=False)
    ours = compare(tree, registry, btcpp_checker, SCRIPTS[name], max_ticks=10,
                   tick_seconds=TICK, halts=True)
    assert any(line.startswith("visit ") for line in ours), ours
    if name == "the controller fails, the recoveries run" and "RoundRobin" in (
            Path(next(p for p in IMPORTED if p.stem == stem)).read_text()):
        assert any(line.split()[1] in RECOVERY_LEAVES for line in ours
                   if line.startswith("visit ")), ours
