"""Nav2's twelve navigator trees against the embedded simulator: no fault, recoverable, not.

Each tree is read from the ROS install or the overlay (never copied here), imported with
our BT.CPP importer and Nav2's palette, and ticked in-process on a node that declares
bt_navigator's parameters (:mod:`sar_testing.nav2_navigators`), with the goal set on the
blackboard as bt_navigator's navigators do. One simulator serves the whole module at
``SPEED``; between runs ``/sar_sim/reset`` puts the robot back at its spawn pose and the
fault parameters are set anew. What ran is read from the runner's own records (the
``status`` events of leaf verdicts and the reason records), never from log text.

The outcomes per tree (docs/reference/nav2-surface.md, "Nav2's navigator trees against the
simulator"):

- ``none``: SUCCESS, the robot at the goal by TF (follow_point: still RUNNING, the robot
  stopped 1 m of path short of the goal, as TruncatePath asks; odometry_calibration: the
  three squares driven, back at their corner).
- ``recoverable``: the trees with a recovery branch clear the phantom ring sealing the goal
  (planner NO_VALID_PATH, then ClearGlobalCostmap-Context) or free a stuck controller
  (FollowPath FAILED_TO_MAKE_PROGRESS, then the RoundRobin's recoveries up to Spin), then
  SUCCESS. A tree without one fails at once with the error code of the failing node.
- ``unrecoverable``: a blocked ring (a real wall) around a goal: NO_VALID_PATH every time;
  the recovery trees give up after their ``number_of_retries`` recoveries.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pytest
from py_trees.common import Status
from sar_testing.processes import NodeProcess
from sar_testing.spin import ros_node

from sar_framework.testing.nav2_navigators import (
    NavigatorBench,
    NavigatorRun,
    declare_navigator_parameters,
    goal_pose,
    import_navigator,
    navigator_trees,
)
from sar_framework.testing.sim_control import sim_process

pytestmark = [pytest.mark.ros, pytest.mark.timeout(600)]
pytest.importorskip("nav2_msgs.action", reason="needs the full nav2_msgs")
#: Simulated seconds per wall second. Measured against the whole matrix at 10x (the
#: reference): at 100x and 150x every run has the same status, recovery leaves, failures
#: and error codes, and ends within 0.07 m of where 10x ends; at 200x a run reports SUCCESS
#: 0.52 m from its goal (ticks too coarse for the simulated motion). 100x leaves margin
#: for a loaded machine (docs/reference/nav2-surface.md).
SPEED = 100.0
TREES = navigator_trees()
GOAL = (2.0, -1.5)  # the south-east room, ~2.5 m from the spawn
WALLED_GOAL = (2.5, 2.5)  # the north-east room, inside BLOCKED_RING
XY_GOAL_TOLERANCE = 0.25  # config/nav2_params.yaml, goal_checker


def ring(x: float, y: float, *, radius: float = 0.6, circles: int = 10,
         circle: float = 0.2) -> list[str]:
    """Circles sealing (x, y) off, the goal itself free (planner: NO_VALID_PATH)."""
    return [f"{x + radius * math.cos(a):.3f}:{y + radius * math.sin(a):.3f}:{circle}"
            for a in (math.tau * i / circles for i in range(circles))]


BLOCKED_RING = ring(*WALLED_GOAL)
PHANTOM_RING = ring(*GOAL)
#: The trees with a recovery branch (a RecoveryNode around the whole navigation).
RECOVERY_TREES = sorted(stem for stem, xml in TREES.items()
                        if 'name="NavigateRecovery"' in xml.read_text())
ROUND_ROBIN = ("ClearGlobalCostmap-Subtree", "Spin", "Wait", "BackUp")


def retries(stem: str) -> int:
    """The tree's own ``number_of_retries`` of its NavigateRecovery (6 in Jazzy's trees)."""
    found = re.search(r'<RecoveryNode number_of_retries="(\d+)" name="NavigateRecovery"',
                      TREES[stem].read_text())
    assert found, stem
    return int(found[1])


@dataclass(frozen=True)
class Case:
    """One cell of the matrix: faults, goal, and what must come out."""

    faults: dict[str, Any] = field(default_factory=dict)
    goal: tuple[float, float] = GOAL
    status: Status = Status.SUCCESS
    ran: tuple[str, ...] = ()  # leaves (by name) that must have SUCCEEDED, in this order
    error: tuple[str, int] | None = None  # (blackboard entry, Nav2 error code)
    failing: str = ""  # the leaf named in the reasons when the tree fails
    says: str = ""  # ... and what its reason says
    recoveries: int | None = None  # RoundRobin recoveries done (the tree's retries)


#: A controller stuck until one recovery motion frees it, with Nav2's allowance
#: (config/nav2_params.yaml; a replanned path keeps the progress clock, as in Nav2).
STUCK_ONCE = {"stuck_recoveries": 1, "movement_time_allowance": 10.0}
NO_FAULTS = {"phantom_obstacles": [], "stuck_recoveries": 0, "movement_time_allowance": 10.0}
NONE, PHANTOM, STUCK, UNRECOVERABLE = "none", "phantom", "stuck", "unrecoverable"
#: odometry_calibration's square: its corner (the robot is brought there first, heading
#: east), free of walls and debris for three 2 m squares turning left.
CORNER = (-4.0, 1.0)
#: A phantom on the square's first side: DriveOnHeading sees a collision ahead.
ON_THE_SQUARE = f"{CORNER[0] + 1.2}:{CORNER[1]}:0.2"


def cases(stem: str) -> dict[str, Case]:
    """The three outcomes of one tree."""
    walled = Case(goal=WALLED_GOAL, status=Status.FAILURE,
                  error=("compute_path_error_code", 208), failing="ComputePathToPose")
    planner = "ComputePathThroughPoses" if "through_poses" in stem else "ComputePathToPose"
    if stem in RECOVERY_TREES:
        return {
            NONE: Case(),
            PHANTOM: Case(faults={"phantom_obstacles": PHANTOM_RING},
                          ran=("ClearGlobalCostmap-Context", "ClearLocalCostmap-Context")),
            STUCK: Case(faults=STUCK_ONCE, ran=("ClearGlobalCostmap-Subtree", "Spin")),
            UNRECOVERABLE: Case(goal=WALLED_GOAL, status=Status.FAILURE,
                                error=("compute_path_error_code", 208),
                                failing=planner, recoveries=retries(stem)),
        }
    if stem == "follow_point":
        return {NONE: Case(status=Status.RUNNING),
                STUCK: Case(faults=STUCK_ONCE, status=Status.FAILURE,
                                  error=("follow_path_error_code", 105), failing="FollowPath"),
                UNRECOVERABLE: walled}
    if stem == "odometry_calibration":
        return {NONE: Case(goal=CORNER),
                UNRECOVERABLE: Case(goal=CORNER, faults={"phantom_obstacles": [ON_THE_SQUARE]},
                                    status=Status.FAILURE, failing="DriveOnHeading",
                                    says="(error code 723)")}  # COLLISION_AHEAD
    return {NONE: Case(),
            STUCK: Case(faults=STUCK_ONCE, status=Status.FAILURE,
                              error=("follow_path_error_code", 105), failing="FollowPath"),
            UNRECOVERABLE: walled}


MATRIX = [(stem, outcome) for stem in TREES for outcome in cases(stem)]


@pytest.fixture(scope="module")
def sim(tmp_path_factory: pytest.TempPathFactory) -> Iterator[NodeProcess]:
    blocked = "[" + ",".join(f"'{c}'" for c in BLOCKED_RING) + "]"
    with sim_process(tmp_path_factory.mktemp("sim"), f"blocked_areas:={blocked}",
                     speed=SPEED) as proc:
        yield proc


@pytest.fixture(scope="module")
def bench(sim: NodeProcess) -> Iterator[NavigatorBench]:
    with ros_node("bt_navigator") as (node, executor):
        declare_navigator_parameters(node)
        yield NavigatorBench(node, executor)


@pytest.fixture(scope="module")
def imported(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    folder = tmp_path_factory.mktemp("navigators")
    return {stem: import_navigator(xml, folder) for stem, xml in TREES.items()}


def test_the_matrix_covers_the_twelve_trees() -> None:
    assert len(TREES) == 12
    assert len(MATRIX) == 4 * len(RECOVERY_TREES) + 3 * (len(TREES) - len(RECOVERY_TREES)) - 1


def blackboard_for(stem: str, goal: tuple[float, float]) -> dict[str, Any]:
    """The entries bt_navigator's navigator sets: ``goal``, or ``goals`` through poses."""
    if "through_poses" in stem:
        return {"goals": [goal_pose(goal[0] / 2, goal[1] / 2), goal_pose(*goal)]}
    return {"goal": goal_pose(*goal)}


def stopped(bench: NavigatorBench) -> Any:
    """A predicate: the robot has come to rest away from the spawn (20 checks in a row)."""
    seen: list[tuple[float, float] | None] = []

    def done() -> bool:
        seen.append(bench.where())
        last = seen[-20:]
        return len(last) == 20 and last[0] is not None and all(
            p is not None and math.dist(p, last[0]) < 0.005 for p in last) \
            and math.dist(last[0], (0.0, 0.0)) > 0.3
    return done


def to_corner(bench: NavigatorBench, imported: dict[str, Path]) -> None:
    """Bring the robot to odometry_calibration's CORNER, heading east, with Nav2's own tree."""
    run = bench.run(imported["navigate_to_pose_w_replanning_and_recovery"],
                    {"goal": goal_pose(*CORNER)}, timeout=20.0)
    assert run.status == Status.SUCCESS, run.summary()


def check(run: NavigatorRun, case: Case) -> None:
    """Assert a run came out as ``case`` says."""
    text = run.summary()
    assert run.status == case.status, text
    if case.status == Status.SUCCESS:
        assert run.pose is not None and math.dist(run.pose, case.goal) <= XY_GOAL_TOLERANCE, text
    succeeded = [(e["name"], e["kind"]) for e in run.events if e["status"] == "SUCCESS"]
    for name in case.ran:  # a leaf's name, or its kind (SpinRecovery is a Spin)
        assert any(name in leaf for leaf in succeeded), f"{name} did not run:\n{text}"
        succeeded = succeeded[[name in leaf for leaf in succeeded].index(True) + 1:]
    if case.error is not None:
        entry, code = case.error
        assert run.blackboard.get(f"/{entry}") == code, text
    if case.failing:
        said = [r["message"] for r in run.reasons
                if r["what"] == "failure" and r["name"] == case.failing]
        assert said and case.says in said[-1], text
    if case.recoveries is not None:
        done = [e for e in run.events if e["status"] == "SUCCESS"
                and (e["name"] in ROUND_ROBIN or e["kind"] in ROUND_ROBIN)]
        assert len(done) == case.recoveries, text


@pytest.mark.parametrize(("stem", "outcome"), MATRIX, ids=[f"{s}-{o}" for s, o in MATRIX])
def test_navigator_tree_against_the_simulator(stem: str, outcome: str, bench: NavigatorBench,
                                              imported: dict[str, Path]) -> None:
    case = cases(stem)[outcome]
    bench.reset(**{**NO_FAULTS, **case.faults})
    if stem == "odometry_calibration":
        to_corner(bench, imported)
    until = stopped(bench) if stem == "follow_point" else None
    run = bench.run(imported[stem], blackboard_for(stem, case.goal), timeout=20.0, until=until)
    if stem == "follow_point" and outcome == NONE:
        assert run.status == Status.RUNNING, run.summary()
        assert run.pose is not None
        left = math.dist(run.pose, case.goal)
        assert 0.7 <= left <= 1.3, run.summary()  # TruncatePath distance="1.0"
        return
    check(run, case)
