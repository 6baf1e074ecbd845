"""Nav2's leaves against the embedded simulator over real DDS, with the real rclpy.

One simulator (``python -m sar_framework.sim``, 30x) and one test node for the module.
The leaves talk to the simulator by Nav2's default names; the test node declares the BT
navigator's ``default_server_timeout`` (2 s: this machine is loaded) as bt_navigator would.
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from py_trees.blackboard import Blackboard
from py_trees.common import Status
from sar_testing.leaf_harness import TreeMaker, tick_until_done, wait_for_service
from sar_testing.processes import NodeProcess
from sar_testing.spin import ros_node, spin_until

from sar_framework.engine.api import load_tree
from sar_framework.testing.nav2_navigators import goal_pose as pose
from sar_framework.testing.sim_control import reset_sim, sim_process

pytestmark = [pytest.mark.ros, pytest.mark.timeout(180)]
pytest.importorskip("nav2_msgs.action", reason="needs the full nav2_msgs")
SPEED = 30.0
DISCOVERY_S = 15.0


@pytest.fixture(scope="module")
def sim(tmp_path_factory: pytest.TempPathFactory) -> Iterator[NodeProcess]:
    with sim_process(tmp_path_factory.mktemp("sim"), speed=SPEED) as proc:
        yield proc


@pytest.fixture(scope="module")
def ros(sim: NodeProcess) -> Iterator[tuple[Any, Any]]:
    from nav2_msgs.action import Spin
    from rclpy.action import ActionClient

    with ros_node("nav2_leaves_test") as (node, executor):
        node.declare_parameter("default_server_timeout", 2000)
        node.declare_parameter("odom_topic", "/odometry/filtered")  # as config/nav2_params
        probe = ActionClient(node, Spin, "spin")
        assert spin_until(executor, probe.server_is_ready, DISCOVERY_S), sim.output
        probe.destroy()
        yield node, executor


@pytest.fixture
def trees(ros: tuple[Any, Any]) -> Iterator[TreeMaker]:
    Blackboard.storage.clear()
    maker = TreeMaker(ros[0])
    yield maker
    maker.shutdown()


def build(tmp_path: Path, text: str) -> Any:
    tree = tmp_path / "t.yaml"
    tree.write_text("format: 1\n" + text)
    return load_tree(tree, {}).root


def run(ros: tuple[Any, Any], trees: TreeMaker, root: Any, timeout: float = 30.0) -> Status:
    return tick_until_done(ros[1], trees(root), timeout)


NAVIGATE = """
blackboard:
  goal: {type: geometry_msgs/msg/PoseStamped}
  path: {type: nav_msgs/msg/Path}
  plan_error: {type: int, initial: -1}
  follow_error: {type: int, initial: -1}
root:
  Sequence:
    children:
      - ComputePathToPose: {goal: "{goal}", path: "{path}", error_code_id: "{plan_error}"}
      - FollowPath: {path: "{path}", error_code_id: "{follow_error}"}
"""
REACHED = """
blackboard:
  goal: {type: geometry_msgs/msg/PoseStamped}
root:
  GoalReached: {goal: "{goal}"}
"""


def test_compute_path_then_follow_it_through_the_blackboard(
        ros: tuple[Any, Any], trees: TreeMaker, tmp_path: Path) -> None:
    root = build(tmp_path, NAVIGATE)
    Blackboard.storage["/goal"] = pose(1.0, -0.5)
    assert run(ros, trees, root) == Status.SUCCESS, [b.feedback_message for b in root.iterate()]
    path = Blackboard.storage["/path"]
    end = path.poses[-1].pose.position
    assert len(path.poses) > 5 and (end.x, end.y) == pytest.approx((1.0, -0.5), abs=0.06)
    assert Blackboard.storage["/plan_error"] == 0
    assert Blackboard.storage["/follow_error"] == 0
    # GoalReached reads TF, which a loaded test process takes one message per spin, after
    # FollowPath's result: tick it until the transforms show the robot where it stopped.
    reached = trees(build(tmp_path, REACHED))
    seen: list[str] = []

    def at_goal() -> bool:
        reached.tick()
        seen.append(reached.root.feedback_message)
        return reached.root.status == Status.SUCCESS

    assert spin_until(ros[1], at_goal, 30.0), seen[-3:]  # outer safety bound


def test_a_goal_in_a_wall_fails_with_nav2s_error_code_and_clears_the_path(
        ros: tuple[Any, Any], trees: TreeMaker, tmp_path: Path) -> None:
    from nav2_msgs.action import ComputePathToPose
    from nav_msgs.msg import Path as PathMsg

    root = build(tmp_path, NAVIGATE)
    Blackboard.storage["/goal"] = pose(0.0, 3.0)  # inside wall_v_top
    Blackboard.storage["/path"] = PathMsg(poses=[pose(0.0, 0.0)])
    assert run(ros, trees, root) == Status.FAILURE
    assert Blackboard.storage["/plan_error"] == ComputePathToPose.Result.GOAL_OCCUPIED
    assert Blackboard.storage["/path"].poses == []  # cleared, as Nav2's on_aborted does
    assert Blackboard.storage["/follow_error"] == -1  # FollowPath never ran


def yaw_from_tf(node: Any, executor: Any, at_least: Any = None) -> float:
    """The robot's yaw from the leaves' TF buffer; with ``at_least``, from a stamp no older."""
    from rclpy.time import Time
    from sar_plugins.nav2._common import yaw_of
    from sar_plugins.nav2._tf import robot_pose

    found: list[Any] = []

    def fresh() -> bool:
        found.append(robot_pose(node, "map", "base_link"))
        return found[-1] is not None and (
            at_least is None or Time.from_msg(found[-1].header.stamp) >= Time.from_msg(at_least))

    assert spin_until(executor, fresh, 10.0), found[-1:]
    return yaw_of(found[-1].pose.orientation)


def test_spin_turns_the_robot_and_counts_a_recovery(
        ros: tuple[Any, Any], trees: TreeMaker, tmp_path: Path) -> None:
    from tf2_msgs.msg import TFMessage

    before = yaw_from_tf(*ros)
    # A loaded test process takes /tf one message per spin while the result overtakes the
    # queue: the turn is read from a /tf message the simulator sent after the result came.
    sent_after: list[Any] = []
    result_at = [float("inf")]
    tf_sub = ros[0].create_subscription(
        TFMessage, "/tf", lambda msg, info: sent_after.append(msg.transforms[-1].header.stamp)
        if info["source_timestamp"] >= result_at[0] else None, 100)
    try:
        root = build(tmp_path, "root:\n  Spin: {spin_dist: 1.57, error_code_id: '{code}'}\n"
                               "blackboard:\n  code: {type: int, initial: -1}\n")
        assert run(ros, trees, root) == Status.SUCCESS
        result_at[0] = time.time_ns()  # the source_timestamp clock (system time)
        assert spin_until(ros[1], lambda: bool(sent_after), 10.0)
        after = yaw_from_tf(*ros, at_least=sent_after[0])
    finally:
        ros[0].destroy_subscription(tf_sub)
    assert Blackboard.storage["/code"] == 0
    assert Blackboard.storage["/number_recoveries"] == 1
    turned = math.remainder(after - before, math.tau)
    assert turned == pytest.approx(1.57, abs=0.15)


def test_backup_wait_and_clear_costmap(ros: tuple[Any, Any], trees: TreeMaker,
                                      tmp_path: Path) -> None:
    from nav2_msgs.srv import ClearEntireCostmap

    wait_for_service(ros[0], ros[1], ClearEntireCostmap,
                     "/local_costmap/clear_entirely_local_costmap")
    # From the spawn, behind the robot is a wall's end: drive ahead into the doorway first,
    # wherever earlier tests left the robot (alone, backing up from the spawn collided).
    assert reset_sim(*ros).success
    root = build(tmp_path, """
root:
  Sequence:
    children:
      - DriveOnHeading: {dist_to_travel: 0.5, speed: 0.25}
      - BackUp: {backup_dist: 0.2, backup_speed: 0.2}
      - Wait: {wait_duration: 2.0}
      - ClearEntireCostmap: {service_name: local_costmap/clear_entirely_local_costmap}
""")
    assert run(ros, trees, root) == Status.SUCCESS, [b.feedback_message for b in root.iterate()]
    # BackUp and Wait, as in Nav2; DriveOnHeading is no recovery
    assert Blackboard.storage["/number_recoveries"] == 2


def test_a_halted_follow_path_cancels_its_goal(ros: tuple[Any, Any], trees: TreeMaker,
                                               tmp_path: Path) -> None:
    root = build(tmp_path, NAVIGATE)
    Blackboard.storage["/goal"] = pose(-3.0, 3.0)  # zone_a: several seconds of driving
    tree = trees(root)
    executor = ros[1]
    follow = next(b for b in root.iterate() if type(b).__name__ == "FollowPath")
    assert spin_until(executor, lambda: follow.status == Status.RUNNING
                      and follow.feedback_message.startswith("goal sent"), 20.0, step=tree.tick)
    spin_until(executor, lambda: False, 0.3, step=tree.tick)
    handle = follow._goals()._handle
    assert handle is not None
    root.stop(Status.INVALID)  # the parent halts the branch
    assert "goal cancelled" in follow.feedback_message
    from action_msgs.msg import GoalStatus

    assert spin_until(executor, lambda: handle.status == GoalStatus.STATUS_CANCELED, 5.0)


DISTANCE = """
blackboard:
  goal: {type: geometry_msgs/msg/PoseStamped}
  path: {type: nav_msgs/msg/Path}
  replan: {type: nav_msgs/msg/Path}
root:
  Sequence:
    children:
      - ComputePathToPose: {goal: "{goal}", path: "{path}"}
      - PipelineSequence:
          children:
            - DistanceController:
                distance: 0.3
                child: {ComputePathToPose: {goal: "{goal}", path: "{replan}"}}
            - FollowPath: {path: "{replan}"}
"""


def test_distance_controller_replans_on_the_runners_robot_state(
        ros: tuple[Any, Any], trees: TreeMaker, tmp_path: Path) -> None:
    """Nav2's replanning-by-distance shape, on the runner's context sources (TF, odometry).

    FollowPath follows each replanned path: before the fix, the simulator's follower never
    finished a path swapped in mid-drive that starts behind the robot.
    """
    from sar_plugins.nav2.robot_context import ROBOT_POSE_KEY, ROBOT_SPEED_KEY

    from sar_framework.ros.robot_state import robot_context

    node, executor = ros
    context = robot_context(node)
    tree_file = tmp_path / "t.yaml"
    tree_file.write_text("format: 1\n" + DISTANCE)
    root = load_tree(tree_file, context).root  # starts the pose source (DistanceController)
    context[ROBOT_SPEED_KEY].start()  # no SpeedController here: started by hand
    assert spin_until(executor, lambda: context[ROBOT_POSE_KEY]("", "") is not None, 10.0)
    start = context[ROBOT_POSE_KEY]("", "")
    far = math.hypot(*start) > 1.0  # free places: the spawn, and where the first test drove
    Blackboard.storage["/goal"] = pose(0.0, 0.0) if far else pose(1.0, -0.5)
    tree = trees(root)
    speeds: list[float] = []
    replans: list[int] = []

    def step() -> None:
        tree.tick()
        speeds.append(context[ROBOT_SPEED_KEY]() or 0.0)
        latest = Blackboard.storage.get("/replan")
        if latest is not None and (not replans or replans[-1] != id(latest)):
            replans.append(id(latest))

    assert spin_until(executor, lambda: root.status == Status.SUCCESS, 30.0, step=step), [
        b.feedback_message for b in root.iterate()]
    assert len(replans) >= 3  # at the start, then every 0.3 m of the ~1.1 m drive
    assert max(speeds) > 0.05  # the odometry source saw the robot move


THROUGH = """
blackboard:
  goals: {type: list}
  path: {type: nav_msgs/msg/Path}
  smooth: {type: nav_msgs/msg/Path}
  controller: {type: str}
  done: {type: bool, initial: false}
root:
  Sequence:
    children:
      - ControllerSelector: {default_controller: FollowPath, selected_controller: "{controller}"}
      - RemovePassedGoals: {input_goals: "{goals}", output_goals: "{goals}", radius: 0.3}
      - ComputePathThroughPoses: {goals: "{goals}", path: "{path}"}
      - SmoothPath: {unsmoothed_path: "{path}", smoothed_path: "{smooth}",
                     was_completed: "{done}"}
      - FollowPath: {path: "{smooth}", controller_id: "{controller}"}
      - CancelControl: {}
"""


def settled_pose(node: Any, executor: Any) -> tuple[float, float]:
    """The robot's (x, y) from the leaves' own TF buffer, once that buffer is current.

    The buffer lags while its subscription still holds older ``/tf`` messages (on a loaded
    machine, up to a queue's worth: the robot seen mid-way through the previous drive), so
    the pose counts once it has stayed put over 1 s of the transforms' own (simulated) time.
    """
    from sar_plugins.nav2._tf import robot_pose

    seen: list[tuple[tuple[float, float], float]] = []

    def at_rest() -> bool:
        now = robot_pose(node, "map", "base_link")
        if now is None:
            return False
        xy = (now.pose.position.x, now.pose.position.y)
        stamp = now.header.stamp.sec + now.header.stamp.nanosec * 1e-9
        if not seen or math.dist(seen[0][0], xy) > 0.01:
            seen[:] = [(xy, stamp)]
            return False
        return stamp - seen[0][1] >= 1.0

    assert spin_until(executor, at_rest, 60.0), f"TF pose never settled: {seen}"
    return seen[0][0]


def test_through_poses_smoothed_and_followed_with_the_selected_controller(
        ros: tuple[Any, Any], trees: TreeMaker, tmp_path: Path) -> None:
    node, executor = ros
    # RemovePassedGoals reads this buffer: read from another, or too early, the robot's own
    # place may be 0.3 m from where the leaf sees it, and three goals stay.
    here = settled_pose(node, executor)
    root = build(tmp_path, THROUGH)
    # the robot's own place first: RemovePassedGoals drops it (within 0.3 m)
    Blackboard.storage["/goals"] = [pose(*here), pose(0.5, -0.3), pose(1.0, -0.5)]
    assert run(ros, trees, root) == Status.SUCCESS, [b.feedback_message for b in root.iterate()]
    assert len(Blackboard.storage["/goals"]) == 2, (
        here, [b.feedback_message for b in root.iterate()])
    assert Blackboard.storage["/controller"] == "FollowPath"
    assert Blackboard.storage["/done"] is True
    end = Blackboard.storage["/smooth"].poses[-1].pose.position
    assert (end.x, end.y) == pytest.approx((1.0, -0.5), abs=0.06)
    assert math.dist(settled_pose(node, executor), (1.0, -0.5)) < 0.3


def test_navigate_to_pose_hands_the_goal_to_the_navigator(
        ros: tuple[Any, Any], trees: TreeMaker, tmp_path: Path) -> None:
    root = build(tmp_path, "blackboard:\n  goal: {type: geometry_msgs/msg/PoseStamped}\n"
                           "  code: {type: int, initial: -1}\n"
                           "root:\n  NavigateToPose: {goal: '{goal}', error_code_id: '{code}'}\n")
    Blackboard.storage["/goal"] = pose(0.0, 3.0)  # inside a wall: the navigator aborts
    assert run(ros, trees, root) == Status.FAILURE
    assert Blackboard.storage["/code"] == 206  # the planner's GOAL_OCCUPIED, as Jazzy's
    Blackboard.storage["/goal"] = pose(0.5, -0.3)
    assert run(ros, trees, root) == Status.SUCCESS
    assert Blackboard.storage["/code"] == 0
