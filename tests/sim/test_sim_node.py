"""The simulator process over real DDS: /clock, lifecycle, AMCL, /map, /tf, odometry, params.

Each class starts one simulator (``python -m sar_framework.sim``) and one client context
for all its tests, so DDS discovery is paid once per class.
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
from sar_testing.processes import NodeProcess
from sar_testing.spin import call_service, ros_node, spin_until

from sar_framework.sim.params import sim_default

pytestmark = pytest.mark.ros
DISCOVERY_S = 15.0
SPEED = 20.0
MAX_UPDATE_HZ = sim_default("max_update_hz")


def sim_args(*params: str) -> list[str]:
    args = ["-m", "sar_framework.sim", "--ros-args"]
    for param in params:
        args += ["-p", param]
    return args


@pytest.fixture(scope="class")
def sim(tmp_path_factory: pytest.TempPathFactory) -> Iterator[NodeProcess]:
    log_dir = tmp_path_factory.mktemp("sim")
    with NodeProcess(sim_args(f"speed:={SPEED}"), "sim", log_dir=log_dir) as proc:
        proc.wait_for_output("ready", timeout=30)
        yield proc


@pytest.fixture(scope="class")
def noloc_sim(tmp_path_factory: pytest.TempPathFactory) -> Iterator[NodeProcess]:
    log_dir = tmp_path_factory.mktemp("sim_noloc")
    with NodeProcess(sim_args(f"speed:={SPEED}", "auto_localize:=false"), "sim",
                     log_dir=log_dir) as proc:
        proc.wait_for_output("ready", timeout=30)
        yield proc


@pytest.fixture(scope="class")
def client() -> Iterator[tuple]:
    with ros_node("sim_node_test") as pair:
        yield pair


def latched():
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

    return QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.TRANSIENT_LOCAL)


def stamp_s(stamp) -> float:
    return stamp.sec + stamp.nanosec * 1e-9


def yaw_of(q) -> float:
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


@pytest.mark.usefixtures("sim")
class TestSimNode:
    def test_clock_runs_at_the_speed_factor(self, client: tuple, sim: NodeProcess) -> None:
        from rosgraph_msgs.msg import Clock

        node, executor = client
        samples: list[tuple[float, float]] = []
        node.create_subscription(
            Clock, "/clock", lambda m: samples.append((time.monotonic(), stamp_s(m.clock))), 10
        )
        assert spin_until(executor, lambda: len(samples) >= 5, DISCOVERY_S), sim.output
        start = samples[-1]
        spin_until(executor, lambda: samples[-1][0] - start[0] >= 2.0, 5.0)
        end = samples[-1]
        rate = (end[1] - start[1]) / (end[0] - start[0])
        assert rate == pytest.approx(SPEED, rel=0.2)
        # Updates are frequent enough for a 2 Hz (simulated) tree tick at this speed: one
        # /clock per max_update_hz period; a loop the machine held up catches up by at most
        # two periods' worth (the lag cap), never by a burst.
        period = SPEED / MAX_UPDATE_HZ
        assert period < 0.5
        gaps = sorted(b[1] - a[1] for a, b in zip(samples[-50:], samples[-49:], strict=False))
        assert gaps[len(gaps) // 2] < 0.5
        assert gaps[-1] <= 2 * period + 0.021  # + one physics step (float rounding)

    @pytest.mark.parametrize("service", ["/amcl/get_state", "/bt_navigator/get_state"])
    def test_lifecycle_reports_active(self, client: tuple, service: str) -> None:
        from lifecycle_msgs.msg import State
        from lifecycle_msgs.srv import GetState

        node, executor = client
        state = call_service(node, executor, GetState, service, GetState.Request(),
                             discovery_timeout=DISCOVERY_S).current_state
        assert (state.id, state.label) == (State.PRIMARY_STATE_ACTIVE, "active")

    def test_initial_pose_is_answered_on_amcl_pose(self, client: tuple) -> None:
        from geometry_msgs.msg import PoseWithCovarianceStamped

        node, executor = client
        answers: list[PoseWithCovarianceStamped] = []
        node.create_subscription(PoseWithCovarianceStamped, "/amcl_pose", answers.append,
                                 latched())
        seed_pub = node.create_publisher(PoseWithCovarianceStamped, "/initialpose", 10)
        seed = PoseWithCovarianceStamped()
        seed.header.frame_id = "map"
        seed.pose.pose.position.x = 0.05
        seed.pose.pose.orientation.w = 1.0

        def seeded() -> list[PoseWithCovarianceStamped]:  # not the latched start-up estimate
            return [a for a in answers if a.pose.pose.position.x == pytest.approx(0.05)]

        deadline = time.monotonic() + DISCOVERY_S
        # waitUntilNav2Active's loop, under an outer safety bound
        while not seeded() and time.monotonic() < deadline:  # outer safety bound
            seed_pub.publish(seed)
            spin_until(executor, lambda: bool(seeded()), 0.5)
        assert seeded(), "no /amcl_pose answer to /initialpose"
        answer = seeded()[-1]
        assert answer.header.frame_id == "map"
        assert answer.pose.pose.position.x == pytest.approx(0.05)
        assert answer.pose.covariance[0] > 0.0  # AMCL's default when the seed has none
        assert 0.0 < stamp_s(answer.header.stamp) < 10_000.0  # simulated time, not epoch

    def test_map_is_latched_with_the_map_files_geometry(self, client: tuple) -> None:
        from nav_msgs.msg import OccupancyGrid

        from sar_framework.sim.occupancy import DEFAULT_MAP_PREFIX, load_map

        node, executor = client
        maps: list[OccupancyGrid] = []
        node.create_subscription(OccupancyGrid, "/map", maps.append, latched())
        assert spin_until(executor, lambda: bool(maps), DISCOVERY_S)
        grid = load_map(DEFAULT_MAP_PREFIX.with_name("final_project_map.yaml"))
        info = maps[0].info
        assert (info.width, info.height) == (grid.width, grid.height)
        assert info.resolution == pytest.approx(0.05)
        assert info.origin.position.x == pytest.approx(grid.origin_x)
        assert list(maps[0].data) == grid.data.ravel().tolist()
        assert maps[0].header.frame_id == "map"

    def test_tf_and_odom_describe_the_robot_at_spawn(self, client: tuple) -> None:
        from nav_msgs.msg import Odometry
        from tf2_msgs.msg import TFMessage

        node, executor = client
        frames: dict[tuple[str, str], object] = {}
        odoms: list[Odometry] = []

        def on_tf(msg: TFMessage) -> None:
            for t in msg.transforms:
                frames[(t.header.frame_id, t.child_frame_id)] = t

        node.create_subscription(TFMessage, "/tf", on_tf, 100)
        node.create_subscription(Odometry, "/odometry/filtered", odoms.append, 10)
        wanted = {("map", "odom"), ("odom", "base_link")}
        assert spin_until(executor, lambda: wanted <= set(frames) and bool(odoms), DISCOVERY_S)
        base = frames[("odom", "base_link")].transform
        assert (base.translation.x, base.translation.y) == pytest.approx((0.0, 0.0), abs=1e-6)
        assert yaw_of(base.rotation) == pytest.approx(0.0, abs=1e-6)
        odom = odoms[-1]
        assert (odom.header.frame_id, odom.child_frame_id) == ("odom", "base_link")
        assert odom.twist.twist.linear.x == 0.0
        assert stamp_s(odom.header.stamp) > 0.0


class TestLocalisation:
    """With ``auto_localize:=false`` the simulator behaves as AMCL before its seed."""

    def test_no_map_frame_and_no_navigation_until_seeded(self, client: tuple,
                                                         noloc_sim: NodeProcess) -> None:
        from action_msgs.msg import GoalStatus
        from geometry_msgs.msg import PoseWithCovarianceStamped
        from nav2_msgs.action import NavigateToPose
        from rclpy.action import ActionClient
        from tf2_msgs.msg import TFMessage

        node, executor = client
        pairs: list[set] = []
        node.create_subscription(
            TFMessage, "/tf",
            lambda m: pairs.append({(t.header.frame_id, t.child_frame_id) for t in m.transforms}),
            100,
        )
        assert spin_until(executor, lambda: len(pairs) >= 5, DISCOVERY_S), noloc_sim.output
        assert all(("map", "odom") not in p for p in pairs)

        action = ActionClient(node, NavigateToPose, "navigate_to_pose")
        assert spin_until(executor, action.server_is_ready, DISCOVERY_S)
        goal = NavigateToPose.Goal()
        goal.pose.header.frame_id = "map"
        goal.pose.pose.position.x = 1.0
        goal.pose.pose.orientation.w = 1.0
        sent = action.send_goal_async(goal)
        assert spin_until(executor, sent.done, 5.0)
        result = sent.result().get_result_async()
        assert spin_until(executor, result.done, 5.0)
        assert result.result().status == GoalStatus.STATUS_ABORTED
        # Jazzy's NavigateToPose has no TF_ERROR: NONE, and bt_navigator's reason.
        assert result.result().result.error_code == NavigateToPose.Result.NONE
        assert "Initial robot pose is not available" in result.result().result.error_msg

        seed = PoseWithCovarianceStamped()
        seed.header.frame_id = "map"
        seed.pose.pose.orientation.w = 1.0
        node.create_publisher(PoseWithCovarianceStamped, "/initialpose", 10).publish(seed)
        assert spin_until(executor, lambda: ("map", "odom") in pairs[-1], 10.0), noloc_sim.output

        sent = action.send_goal_async(goal)
        assert spin_until(executor, sent.done, 5.0)
        result = sent.result().get_result_async()
        assert spin_until(executor, result.done, 20.0)
        assert result.result().status == GoalStatus.STATUS_SUCCEEDED


@pytest.mark.parametrize(
    ("param", "message"),
    [
        ("speed:=-2.0", "parameter speed: must be > 0 and <= 1000, got -2.0"),
        ("blocked_areas:=['nowhere']", "blocked_areas: 'nowhere'"),
        ("map_yaml:=/no/such/map.yaml",
         "parameter map_yaml: /no/such/map.yaml: cannot read map yaml"),
        ("spawn_x:=50.0", "parameters spawn_x, spawn_y on "),
        ("spawn_y:=5.0", "(0, 5) is not free on the map (occupied)"),
        ("trace_file:=/proc/no/trace.jsonl", "parameter trace_file: cannot write"),
    ],
)
def test_invalid_settings_exit_with_status_2(tmp_path: Path, param: str, message: str) -> None:
    proc = NodeProcess(sim_args(param), "bad", log_dir=tmp_path).start()
    assert proc.wait(timeout=30) == 2, proc.output
    assert message in proc.output
