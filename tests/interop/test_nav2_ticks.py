"""Nav2's navigator trees ticked with scripted leaves, by py_trees and by BehaviorTree.CPP.

Each of the seven navigator trees whose Nav2 nodes the checker has stand-ins for is
imported with Nav2's palette (its leaves are ``sar_plugins.nav2``'s), exported again, and
ticked on both sides with the same scripted leaf results (here every leaf of the registry
is replaced by a scripted one of the same name and ports; the checker registers every
leaf of the export's ``<TreeNodesModel>`` as a scripted leaf); the transcripts (leaf
visits, halts, root status per tick) must be equal. Ticks are 400 ms apart on a tick clock
on both sides (our side steps its clock, the checker's stand-ins read its tick clock; no
BT.CPP timer is in these trees, so nothing sleeps), so the RateControllers (1, 2 and
0.333 Hz) re-tick their planner on the same tick on both sides.

Nav2's control nodes are not in BT.CPP: the checker ticks them with stand-ins written
from Nav2's documented behaviour (``btcpp_checker/nav2_standins.h``, no Nav2 code). The
five decorators that read the robot or ROS messages are driven in a reduced form both
sides are fed alike: the robot moves along x at ``SPEED`` m/s on the tick clock (pose
``(SPEED * (tick - 1) * TICK, 0)``, given to our side through the build context's
``robot_pose``/``robot_speed`` sources, to the checker by ``speed=``), so
DistanceController (1 m) re-ticks its planner every fifth tick and SpeedController
(speed above max_speed: 1 Hz) every third; new goals are set at given ticks (the root
entry ``goal`` becomes the string ``"goal N"`` before tick N, on both sides), so
GoalUpdatedController and SpeedController re-plan then, and GoalUpdater, which never
receives a goal on its topic here, passes each through; the checker has no
``nav_msgs/Path``, and no scripted leaf writes ``{path}``, so PathLongerOnApproach never
ticks its child on either side. Goals received by GoalUpdater and paths becoming longer
are checked only on our side (``tests/engine/nodes/test_nav2_decorators.py``,
``test_nav2_robot.py``).
Our own nodes are checked
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
#: The robot's speed (m/s): 0.22 m a tick, no distance or period falls on a tick.
SPEED = 0.55
#: Nav2's decorators driven in the reduced form (see the module docstring).
REDUCED = {"GoalUpdatedController", "PathLongerOnApproach", "DistanceController",
           "SpeedController", "GoalUpdater"}
IMPORTED = list(NAVIGATORS)
#: The navigators that use them.
REDUCED_TREES = [p.stem for p in NAVIGATORS if tags(read_xml(p)) & REDUCED]

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
#: Scripts run only on REDUCED_TREES: a long drive shows the decorators' gating.
LONG_DRIVE: Script = {"FollowPath": ["RUNNING"] * 11 + ["SUCCESS"]}
#: name -> ticks before which a new goal is set ("goal N" in the root entry ``goal``).
GATING: dict[str, tuple[int, ...]] = {
    "the controller runs long": (),
    "the controller runs long, new goals before ticks 3 and 7": (3, 7),
}
#: (stem, name) -> ticks on which the gated planner is visited.
PLANNER_TICKS = {
    # 1 m at 0.22 m a tick; goals do not matter
    ("navigate_w_replanning_distance", "the controller runs long"): [1, 6, 11],
    ("navigate_w_replanning_distance",
     "the controller runs long, new goals before ticks 3 and 7"): [1, 6, 11],
    # 1 Hz at 0.4 s a tick; a new goal re-plans at once and restarts the period
    ("navigate_w_replanning_speed", "the controller runs long"): [1, 4, 7, 10],
    ("navigate_w_replanning_speed",
     "the controller runs long, new goals before ticks 3 and 7"): [1, 3, 6, 7, 10],
    ("navigate_w_replanning_only_if_goal_is_updated", "the controller runs long"): [1],
    ("navigate_w_replanning_only_if_goal_is_updated",
     "the controller runs long, new goals before ticks 3 and 7"): [1, 3, 7],
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
GATING_CASES = [(stem, name) for stem in REDUCED_TREES for name in GATING]


@pytest.mark.parametrize(("stem", "name"), CASES, ids=[f"{s}-{n}" for s, n in CASES])
def test_navigator_ticks_as_btcpp_does(stem: str, name: str, btcpp_checker: Path,
                                       imported: dict[str, Path]) -> None:
    tree = imported[stem]
    registry = discover(entry_points=False)
    ours = compare(tree, registry, btcpp_checker, SCRIPTS[name], max_ticks=10,
                   tick_seconds=TICK, sleeps=False, halts=True, speed=SPEED)
    assert any(line.startswith("visit ") for line in ours), ours
    if name == "the controller fails, the recoveries run" and "RoundRobin" in (
            Path(next(p for p in IMPORTED if p.stem == stem)).read_text()):
        assert any(line.split()[1] in RECOVERY_LEAVES for line in ours
                   if line.startswith("visit ")), ours


def test_reduced_trees_are_the_five() -> None:
    assert len(REDUCED_TREES) == 5, REDUCED_TREES
    assert {stem for stem, _ in PLANNER_TICKS} <= set(REDUCED_TREES)


def planner_ticks(lines: list[str]) -> list[int]:
    """The ticks on which a planner leaf was visited."""
    ticks, tick = [], 1
    for line in lines:
        if line.startswith("tick "):
            tick = int(line.split()[1]) + 1
        elif line.split()[1] in ("ComputePathToPose", "ComputePathThroughPoses") and (
                not ticks or ticks[-1] != tick):
            ticks.append(tick)
    return ticks


@pytest.mark.parametrize(("stem", "name"), GATING_CASES,
                         ids=[f"{s}-{n}" for s, n in GATING_CASES])
def test_nav2_decorator_gating_ticks_as_btcpp_does(stem: str, name: str, btcpp_checker: Path,
                                                   imported: dict[str, Path]) -> None:
    ours = compare(imported[stem], discover(entry_points=False), btcpp_checker,
                   LONG_DRIVE, max_ticks=12, tick_seconds=TICK, sleeps=False, halts=True,
                   speed=SPEED,
                   goal_ticks=GATING[name])
    assert ours[-1].startswith("tick 12 "), ours  # follow_point keeps following
    if (stem, name) in PLANNER_TICKS:
        assert ours[-1] == "tick 12 SUCCESS", ours
        assert planner_ticks(ours) == PLANNER_TICKS[stem, name], ours
