"""Nav2's leaves against the simulator's faults, over real DDS with the real rclpy.

One simulator for the module (40x, a ``blocked_areas`` wall at (2.0, -1.5)); faults are set
at run time with SetParameters, and ``/sar_sim/reset`` puts the robot back after each test.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from py_trees.blackboard import Blackboard
from py_trees.common import Status
from sar_testing.leaf_harness import TreeMaker, tick_until_done, wait_for_service
from sar_testing.processes import NodeProcess
from sar_testing.spin import ros_node

from sar_framework.engine.api import load_tree
from sar_framework.sim.messages import pose_stamped
from sar_framework.sim.world import Pose2D
from sar_framework.testing.sim_control import odometry_xy, reset_sim, set_sim_params, sim_process

pytestmark = [pytest.mark.ros, pytest.mark.timeout(180)]
pytest.importorskip("nav2_msgs.action", reason="needs the full nav2_msgs")
GOAL = (1.0, -0.5)
MESSAGES: list[str] = []
"""The last tree's feedback messages (for assertion messages)."""
WALL = (2.0, -1.5)


@pytest.fixture(scope="module")
def sim(tmp_path_factory: pytest.TempPathFactory) -> Iterator[NodeProcess]:
    wall = f"blocked_areas:=['{WALL[0]}:{WALL[1]}:0.3']"
    with sim_process(tmp_path_factory.mktemp("sim"), wall, speed=40.0) as proc:
        yield proc


@pytest.fixture(scope="module")
def ros(sim: NodeProcess) -> Iterator[tuple[Any, Any]]:
    from nav2_msgs.srv import IsPathValid

    with ros_node("nav2_faults_test") as (node, executor):
        node.declare_parameter("default_server_timeout", 2000)
        wait_for_service(node, executor, IsPathValid, "is_path_valid")
        yield node, executor


@pytest.fixture
def trees(ros: tuple[Any, Any]) -> Iterator[TreeMaker]:
    """A tree maker on a clean blackboard; afterwards, faults unset and the robot reset."""
    maker = TreeMaker(ros[0])
    Blackboard.storage.clear()
    try:
        yield maker
    finally:
        maker.shutdown()
        set_params(ros, phantom_obstacles=[""], stuck_recoveries=0,
                   movement_time_allowance=10.0)
        answer = reset_sim(*ros)
        assert answer.success, answer.message


def set_params(ros: tuple[Any, Any], **values: Any) -> None:
    results = set_sim_params(*ros, **values)
    assert all(r.successful for r in results), [r.reason for r in results]


def pose(x: float, y: float) -> Any:
    return pose_stamped(Pose2D(x, y, 0.0), "map", 0)


def run(ros: tuple[Any, Any], trees: TreeMaker, tmp_path: Path, text: str,
        timeout: float = 30.0) -> Status:
    tree = tmp_path / "t.yaml"
    tree.write_text("format: 1\n" + text)
    root = load_tree(tree, {}).root
    status = tick_until_done(ros[1], trees(root), timeout)
    MESSAGES[:] = [f"{b.name}: {b.feedback_message}" for b in root.iterate()]
    return status


BOARD = """
blackboard:
  goal: {type: geometry_msgs/msg/PoseStamped}
  path: {type: nav_msgs/msg/Path}
  plan_error: {type: int, initial: -1}
  follow_error: {type: int, initial: -1}
"""
PLAN = BOARD + """root:
  ComputePathToPose: {goal: "{goal}", path: "{path}", error_code_id: "{plan_error}"}
"""
FOLLOW = BOARD + """root:
  FollowPath: {path: "{path}", error_code_id: "{follow_error}"}
"""
NAVIGATE = BOARD + """root:
  Sequence:
    children:
      - ComputePathToPose: {goal: "{goal}", path: "{path}", error_code_id: "{plan_error}"}
      - FollowPath: {path: "{path}", error_code_id: "{follow_error}"}
"""


def clear(which: str) -> str:
    return (f"root:\n  ClearEntireCostmap: {{service_name: "
            f"{which}_costmap/clear_entirely_{which}_costmap}}\n")


def test_a_phantom_at_the_goal_is_cleared_from_the_global_costmap_then_planning_succeeds(
        ros: tuple[Any, Any], trees: TreeMaker, tmp_path: Path) -> None:
    set_params(ros, phantom_obstacles=[f"{GOAL[0]}:{GOAL[1]}:0.3"])
    Blackboard.storage["/goal"] = pose(*GOAL)
    assert run(ros, trees, tmp_path, PLAN) == Status.FAILURE
    assert Blackboard.storage["/plan_error"] == 206  # GOAL_OCCUPIED
    assert run(ros, trees, tmp_path, clear("local")) == Status.SUCCESS
    assert run(ros, trees, tmp_path, PLAN) == Status.FAILURE  # the global one still has it
    assert run(ros, trees, tmp_path, clear("global")) == Status.SUCCESS
    assert run(ros, trees, tmp_path, PLAN) == Status.SUCCESS, MESSAGES
    assert Blackboard.storage["/plan_error"] == 0


def test_a_blocked_zones_wall_stays_after_clearing(
        ros: tuple[Any, Any], trees: TreeMaker, tmp_path: Path) -> None:
    Blackboard.storage["/goal"] = pose(*WALL)
    assert run(ros, trees, tmp_path, clear("global")) == Status.SUCCESS
    assert run(ros, trees, tmp_path, PLAN) == Status.FAILURE
    assert Blackboard.storage["/plan_error"] == 206


def test_a_local_phantom_stops_follow_path_until_the_local_costmap_is_cleared(
        ros: tuple[Any, Any], trees: TreeMaker, tmp_path: Path) -> None:
    Blackboard.storage["/goal"] = pose(*GOAL)
    assert run(ros, trees, tmp_path, PLAN) == Status.SUCCESS
    set_params(ros, phantom_obstacles=["0.5:-0.25:0.15"])  # on the path
    assert run(ros, trees, tmp_path, FOLLOW) == Status.FAILURE
    assert Blackboard.storage["/follow_error"] == 106  # NO_VALID_CONTROL
    assert run(ros, trees, tmp_path, clear("local")) == Status.SUCCESS
    assert run(ros, trees, tmp_path, FOLLOW) == Status.SUCCESS, MESSAGES


def test_is_path_valid_is_false_across_a_phantom_and_true_once_cleared(
        ros: tuple[Any, Any], trees: TreeMaker, tmp_path: Path) -> None:
    Blackboard.storage["/goal"] = pose(*GOAL)
    assert run(ros, trees, tmp_path, PLAN) == Status.SUCCESS
    valid = BOARD + 'root:\n  IsPathValid: {path: "{path}", server_timeout: 2000}\n'
    assert run(ros, trees, tmp_path, valid) == Status.SUCCESS
    set_params(ros, phantom_obstacles=["0.5:-0.25:0.15"])
    assert run(ros, trees, tmp_path, valid) == Status.FAILURE
    around = ("root:\n  ClearCostmapAroundRobot: {reset_distance: 2.0, service_name: "
              "global_costmap/clear_around_global_costmap}\n")
    assert run(ros, trees, tmp_path, around) == Status.SUCCESS
    assert run(ros, trees, tmp_path, valid) == Status.SUCCESS


def test_a_stuck_controller_fails_with_105_and_a_spin_frees_it(
        ros: tuple[Any, Any], trees: TreeMaker, tmp_path: Path) -> None:
    set_params(ros, stuck_recoveries=1, movement_time_allowance=4.0)
    Blackboard.storage["/goal"] = pose(*GOAL)
    assert run(ros, trees, tmp_path, NAVIGATE) == Status.FAILURE
    assert Blackboard.storage["/plan_error"] == 0
    assert Blackboard.storage["/follow_error"] == 105  # FAILED_TO_MAKE_PROGRESS
    assert run(ros, trees, tmp_path, "root:\n  Spin: {spin_dist: 1.0}\n") == Status.SUCCESS
    assert run(ros, trees, tmp_path, NAVIGATE) == Status.SUCCESS, MESSAGES
    assert Blackboard.storage["/follow_error"] == 0


def test_drive_on_heading_moves_the_robot_and_refuses_a_mismatched_sign(
        ros: tuple[Any, Any], trees: TreeMaker, tmp_path: Path) -> None:
    drive = ("blackboard:\n  code: {type: int, initial: -1}\n"
             "root:\n  DriveOnHeading: {dist_to_travel: %s, speed: %s, error_code_id: "
             "'{code}'}\n")
    assert run(ros, trees, tmp_path, drive % (0.4, 0.2)) == Status.SUCCESS, MESSAGES
    assert odometry_xy(*ros)[0] == pytest.approx(0.4, abs=0.05)
    assert run(ros, trees, tmp_path, drive % (0.4, -0.2)) == Status.FAILURE
    assert Blackboard.storage["/code"] == 724  # INVALID_INPUT


@pytest.mark.parametrize(("text", "key", "code"), [
    ('root:\n  ComputePathToPose: {goal: "{goal}", planner_id: Nope, '
     'error_code_id: "{plan_error}"}\n', "/plan_error", 201),
    ('root:\n  FollowPath: {path: "{path}", controller_id: Nope, '
     'error_code_id: "{follow_error}"}\n', "/follow_error", 101),
])
def test_an_unknown_plugin_id_fails_with_nav2s_code(
        ros: tuple[Any, Any], trees: TreeMaker, tmp_path: Path, text: str, key: str,
        code: int) -> None:
    Blackboard.storage["/goal"] = pose(*GOAL)
    assert run(ros, trees, tmp_path, PLAN) == Status.SUCCESS
    assert run(ros, trees, tmp_path, BOARD + text) == Status.FAILURE
    assert Blackboard.storage[key] == code


def test_the_navigator_reports_a_stuck_controllers_105_until_a_drive_frees_it(
        ros: tuple[Any, Any], trees: TreeMaker, tmp_path: Path) -> None:
    set_params(ros, stuck_recoveries=1, movement_time_allowance=3.0)
    Blackboard.storage["/goal"] = pose(*GOAL)
    navigate = ("blackboard:\n  goal: {type: geometry_msgs/msg/PoseStamped}\n"
                "  code: {type: int, initial: -1}\n"
                "root:\n  NavigateToPose: {goal: '{goal}', error_code_id: '{code}'}\n")
    assert run(ros, trees, tmp_path, navigate) == Status.FAILURE
    assert Blackboard.storage["/code"] == 105
    drive = "root:\n  DriveOnHeading: {dist_to_travel: 0.2, speed: 0.2}\n"
    assert run(ros, trees, tmp_path, drive) == Status.SUCCESS, MESSAGES
    assert run(ros, trees, tmp_path, navigate) == Status.SUCCESS, MESSAGES
    assert Blackboard.storage["/code"] == 0
