"""Two robots in one simulator over real DDS: namespaced Nav2, shared world, two runners.

One simulator for the module: ``robot1`` stands in the hub's only
north-south doorway, ``robot2`` starts in the north-east room. The tests run in file order:
the doorway first, then both robots drive at once, then a runner per namespace.
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
from sar_testing.processes import NodeProcess
from sar_testing.spin import call_service, ros_node, spin_until

pytestmark = pytest.mark.ros

REPO = Path(__file__).resolve().parents[2]
DISCOVERY_S = 15.0
SPEED = 30.0
SPAWNS = {"robot1": (0.5, 0.0, 1.57), "robot2": (2.0, 1.0, 0.0)}
FLEET = "robots:\n" + "".join(
    f"  - name: {name}\n    pose: {{x: {x}, y: {y}, yaw: {yaw}}}\n"
    for name, (x, y, yaw) in SPAWNS.items())
NAV_TREE = """\
format: 1
name: fleet_visit
root:
  sequence:
    name: Visit
    memory: true
    children:
      - ZonesRemaining: {name: "ZonesRemaining?"}
      - NavigateToZone: {}
      - AdvanceZone: {}
"""


@pytest.fixture(scope="module")
def sim(tmp_path_factory: pytest.TempPathFactory) -> Iterator[NodeProcess]:
    log_dir = tmp_path_factory.mktemp("fleet")
    fleet = log_dir / "fleet.yaml"
    fleet.write_text(FLEET, encoding="utf-8")
    args = ["-m", "sar_framework.sim", "--ros-args", "-p", f"speed:={SPEED}",
            "-p", f"fleet_file:={fleet}", "-p", f"trace_file:={log_dir / 'trace.jsonl'}"]
    with NodeProcess(args, "sim", log_dir=log_dir) as proc:
        proc.wait_for_output("ready", timeout=30)
        yield proc


@pytest.fixture(scope="module")
def client(sim: NodeProcess) -> Iterator[tuple]:
    with ros_node("fleet_test") as pair:
        yield pair


def navigate(node, executor, goals: dict[str, tuple[float, float, float]],
             timeout: float = 60.0) -> dict[str, object]:
    """Send each robot its goal at once; return each result (status, error_code)."""
    from nav2_msgs.action import NavigateToPose
    from rclpy.action import ActionClient

    clients = {ns: ActionClient(node, NavigateToPose, f"/{ns}/navigate_to_pose")
               for ns in goals}
    for ns, action in clients.items():
        assert action.wait_for_server(timeout_sec=DISCOVERY_S), f"/{ns}/navigate_to_pose"
    sent = {}
    for ns, (x, y, yaw) in goals.items():
        goal = NavigateToPose.Goal()
        goal.pose.header.frame_id = "map"
        goal.pose.pose.position.x, goal.pose.pose.position.y = x, y
        goal.pose.pose.orientation.z = math.sin(yaw / 2.0)
        goal.pose.pose.orientation.w = math.cos(yaw / 2.0)
        sent[ns] = clients[ns].send_goal_async(goal)
    assert spin_until(executor, lambda: all(f.done() for f in sent.values()), 10.0)
    handles = {ns: f.result() for ns, f in sent.items()}
    assert all(h.accepted for h in handles.values())
    results = {ns: h.get_result_async() for ns, h in handles.items()}
    assert spin_until(executor, lambda: all(f.done() for f in results.values()), timeout)
    return {ns: f.result() for ns, f in results.items()}


def pose_of(node, executor, ns: str) -> tuple[float, float]:
    """The robot's map pose from its own ``/ns/amcl_pose``."""
    from geometry_msgs.msg import PoseWithCovarianceStamped
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

    got: list = []
    qos = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
    sub = node.create_subscription(PoseWithCovarianceStamped, f"/{ns}/amcl_pose",
                                   got.append, qos)
    try:
        assert spin_until(executor, lambda: bool(got), DISCOVERY_S)
    finally:
        node.destroy_subscription(sub)
    p = got[-1].pose.pose.position
    return p.x, p.y


@pytest.mark.parametrize("ns", sorted(SPAWNS))
def test_each_robot_has_nav2_s_surface_under_its_namespace(client: tuple, ns: str) -> None:
    from lifecycle_msgs.msg import State
    from lifecycle_msgs.srv import GetState
    from nav_msgs.msg import Odometry
    from tf2_msgs.msg import TFMessage

    node, executor = client
    for server in ("amcl", "bt_navigator", "planner_server", "controller_server",
                   "global_costmap/global_costmap"):
        state = call_service(node, executor, GetState, f"/{ns}/{server}/get_state",
                             GetState.Request(), discovery_timeout=DISCOVERY_S).current_state
        assert state.id == State.PRIMARY_STATE_ACTIVE, server
    wanted = {("lifecycle_manager_navigation", f"/{ns}"),
              ("lifecycle_manager_localization", f"/{ns}"), ("map_server", f"/{ns}")}
    # Node names come by discovery, which may lag the services answering on a loaded machine.
    assert spin_until(executor, lambda: wanted <= set(node.get_node_names_and_namespaces()),
                      DISCOVERY_S), node.get_node_names_and_namespaces()
    tf: list[TFMessage] = []
    odom: list[Odometry] = []
    node.create_subscription(TFMessage, f"/{ns}/tf", tf.append, 10)
    node.create_subscription(Odometry, f"/{ns}/odometry/filtered", odom.append, 10)
    frames = set()

    def seen_both() -> bool:
        frames.update((t.header.frame_id, t.child_frame_id) for m in tf for t in m.transforms)
        return {("map", "odom"), ("odom", "base_link")} <= frames and bool(odom)

    assert spin_until(executor, seen_both, DISCOVERY_S), frames
    x, y = pose_of(node, executor, ns)
    assert (x, y) == pytest.approx(SPAWNS[ns][:2], abs=0.05)
    names = {name for name, _ in node.get_service_names_and_types()}
    assert "/navigate_to_pose/_action/send_goal" not in names  # nothing in the root


def test_a_robot_in_the_only_doorway_fails_the_other_s_plan(client: tuple) -> None:
    from action_msgs.msg import GoalStatus

    node, executor = client
    result = navigate(node, executor, {"robot2": (4.0, -3.0, 0.0)})["robot2"]
    assert result.status == GoalStatus.STATUS_ABORTED
    assert result.result.error_code == 208  # ComputePathToPose NO_VALID_PATH
    assert plan_error(node, executor, "robot2", (4.0, -3.0)) == 208  # its own planner
    assert plan_error(node, executor, "robot1", (4.0, -3.0)) == 0  # robot1 is not blocked


def plan_error(node, executor, ns: str, goal_xy: tuple[float, float]) -> int:
    """``/ns/compute_path_to_pose``'s error code for a plan from the robot to ``goal_xy``."""
    nav2_action = pytest.importorskip("nav2_msgs.action")
    if not hasattr(nav2_action, "ComputePathToPose"):
        pytest.skip("the stand-in nav2_msgs has NavigateToPose only")
    from rclpy.action import ActionClient

    action = ActionClient(node, nav2_action.ComputePathToPose, f"/{ns}/compute_path_to_pose")
    assert action.wait_for_server(timeout_sec=DISCOVERY_S)
    goal = nav2_action.ComputePathToPose.Goal(use_start=False)
    goal.goal.header.frame_id = "map"
    goal.goal.pose.position.x, goal.goal.pose.position.y = goal_xy
    goal.goal.pose.orientation.w = 1.0
    sent = action.send_goal_async(goal)
    assert spin_until(executor, sent.done, 10.0)
    result = sent.result().get_result_async()
    assert spin_until(executor, result.done, 10.0)
    action.destroy()
    return result.result().result.error_code


def test_both_robots_navigate_at_once_and_arrive(client: tuple) -> None:
    from action_msgs.msg import GoalStatus

    node, executor = client
    goals = {"robot1": (-3.5, -3.0, 0.0), "robot2": (2.0, 3.5, 0.0)}
    results = navigate(node, executor, goals)
    assert {ns: r.status for ns, r in results.items()} == {
        "robot1": GoalStatus.STATUS_SUCCEEDED, "robot2": GoalStatus.STATUS_SUCCEEDED}
    for ns, (x, y, _) in goals.items():
        assert pose_of(node, executor, ns) == pytest.approx((x, y), abs=0.3)


def test_each_robot_has_its_own_trace_in_a_folder_of_its_name(sim: NodeProcess) -> None:
    """One trace per robot (DIR/<name>/trace.jsonl): its spawn, its goals, its path."""
    import json

    folder = sim.log_path.parent
    assert not (folder / "trace.jsonl").exists()
    for ns, (x, y, yaw) in SPAWNS.items():
        path = folder / ns / "trace.jsonl"
        deadline = time.monotonic() + 30.0  # outer safety bound (flushed every wall second)
        while '"accepted"' not in path.read_text():
            assert time.monotonic() < deadline, f"no goal accepted in {path}"  # outer safety bound
            time.sleep(0.2)
        records = [json.loads(line) for line in path.read_text().splitlines()]
        start = records[0]
        assert (start["event"], start["x"], start["y"], start["yaw"]) == ("start", x, y, yaw)
        accepted = [r for r in records if r.get("event") == "accepted"]
        assert accepted, ns  # the goals of the tests above, this robot's only
        goals = {"robot1": (-3.5, -3.0), "robot2": (2.0, 3.5)}
        assert (accepted[-1]["x"], accepted[-1]["y"]) == goals[ns]


@pytest.mark.usefixtures("sim")
def test_nav2_start_up_in_a_namespace_waits_for_that_robot_s_nodes() -> None:
    """The runner's start-up: seed ``/robot2/amcl``, wait for ``/robot2/bt_navigator``.

    Our rclpy path (used on a given context, and where nav2_simple_commander is not
    installed); BasicNavigator's names are relative already (the runners' test below).
    """
    import rclpy
    from rclpy.context import Context

    from sar_framework.runner.nav2_startup import InitialPose, seed_amcl_and_wait_for_nav2

    context = Context()
    rclpy.init(args=["x", "--ros-args", "-r", "__ns:=/robot2"], context=context)
    try:
        seed_amcl_and_wait_for_nav2(
            pose=InitialPose(2.0, 3.5), timeout_s=15.0, context=context,
            prefer_basic_navigator=False)
    finally:
        rclpy.try_shutdown(context=context)


def test_two_runners_in_two_namespaces_tick_the_same_tree(client: tuple,
                                                          tmp_path: Path) -> None:
    tree = tmp_path / "visit.yaml"
    tree.write_text(NAV_TREE, encoding="utf-8")
    plan = {"robot1": ("zone_a", (-3.5, -3.0)), "robot2": ("zone_b", (2.0, 3.5))}
    runners = []
    for ns, (zone, (x, y)) in plan.items():
        args = ["-m", "sar_framework.runner.node", "--ros-args", "-r", f"__ns:=/{ns}",
                "--params-file", str(REPO / "config" / "mission_params.yaml"),
                "-p", f"tree:={tree}", "-p", f"zone_order:=[{zone}]",
                "-p", f"initial_pose.x:={x}", "-p", f"initial_pose.y:={y}",
                "-p", "exit_on_completion:=true", "-p", "tick_rate_hz:=10.0"]
        runners.append(NodeProcess(args, f"runner_{ns}", log_dir=tmp_path).start())
    try:
        codes = [runner.wait(timeout=90.0) for runner in runners]
    finally:
        for runner in runners:
            runner.stop()
    outputs = "\n".join(r.output for r in runners)
    assert codes == [0, 0], outputs
    node, executor = client
    assert pose_of(node, executor, "robot1") == pytest.approx((-3.0, 3.0), abs=0.3)
    assert pose_of(node, executor, "robot2") == pytest.approx((3.5, 3.0), abs=0.3)
