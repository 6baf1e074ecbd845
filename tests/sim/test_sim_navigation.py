"""navigate_to_pose against the simulator process over real DDS: goals, faults, shutdown.

Each class starts its own simulator (with that class's fault parameters) and one client
context, so DDS discovery is paid once per class; classes run one after another, so two
simulators never share the test run's domain.
"""

from __future__ import annotations

import itertools
import math
import signal
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pytest
from sar_testing.processes import NodeProcess
from sar_testing.spin import ros_node, spin_until

pytestmark = pytest.mark.ros
DISCOVERY_S = 15.0
SPEED = 30.0
ZONE_A = (-3.0, 3.0, 0.0)
ZONE_C = (4.0, -3.0, 3.14)
ZONE_D = (-3.5, -3.0, -1.57)
BASE = (0.0, 0.0, 0.0)
SEAL_ZONE_A_ROOM = "-0.5:0.85:0.8"  # a disk over the north-west room's doorway


def start_sim(log_dir: Path, *params: str) -> NodeProcess:
    args = ["-m", "sar_framework.sim", "--ros-args"]
    for param in params:
        args += ["-p", param]
    proc = NodeProcess(args, "sim", log_dir=log_dir).start()
    proc.wait_for_output("ready", timeout=30)
    return proc


def yaw_of(q: Any) -> float:
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


@dataclass
class GoalRun:
    """One goal sent by :class:`SimClient`."""

    handle: Any
    feedback: list[Any] = field(default_factory=list)
    result: Any = None

    @property
    def accepted(self) -> bool:
        return bool(self.handle is not None and self.handle.accepted)


class SimClient:
    """A navigate_to_pose client plus an /odometry/filtered listener on one test node."""

    def __init__(self, node: Any, executor: Any) -> None:
        from nav2_msgs.action import NavigateToPose
        from nav_msgs.msg import Odometry
        from rclpy.action import ActionClient

        self.node, self.executor = node, executor
        self.action_type = NavigateToPose
        self.action = ActionClient(node, NavigateToPose, "navigate_to_pose")
        self.odom: list[Odometry] = []
        # Deep enough to keep every message of a drive however late the executor takes
        # them: a loaded machine must not thin out the speeds a test reads.
        node.create_subscription(Odometry, "/odometry/filtered", self.odom.append, 1000)

    def wait_ready(self, sim: NodeProcess) -> None:
        ready = lambda: self.action.server_is_ready() and bool(self.odom)  # noqa: E731
        assert spin_until(self.executor, ready, DISCOVERY_S), sim.output

    def spin(self, seconds: float) -> None:
        spin_until(self.executor, lambda: False, seconds)

    def send(self, x: float, y: float, yaw: float, frame: str = "map",
             timeout: float = 10.0) -> GoalRun:
        goal = self.action_type.Goal()
        goal.pose.header.frame_id = frame
        goal.pose.pose.position.x, goal.pose.pose.position.y = x, y
        goal.pose.pose.orientation.z = math.sin(yaw / 2.0)
        goal.pose.pose.orientation.w = math.cos(yaw / 2.0)
        run = GoalRun(handle=None)
        sent = self.action.send_goal_async(
            goal, feedback_callback=lambda msg: run.feedback.append(msg.feedback)
        )
        assert spin_until(self.executor, sent.done, timeout), "no answer to the goal request"
        run.handle = sent.result()
        if run.accepted:
            run.result = run.handle.get_result_async()
        return run

    def finish(self, run: GoalRun, timeout: float = 20.0) -> tuple[int, Any]:
        assert spin_until(self.executor, run.result.done, timeout), "goal never ended"
        response = run.result.result()
        return response.status, response.result

    def go(self, x: float, y: float, yaw: float, timeout: float = 20.0) -> tuple[int, Any]:
        run = self.send(x, y, yaw)
        assert run.accepted
        return self.finish(run, timeout)

    def robot(self) -> tuple[float, float, float]:
        pose = self.odom[-1].pose.pose
        return pose.position.x, pose.position.y, yaw_of(pose.orientation)


@pytest.fixture(scope="class")
def client() -> Iterator[SimClient]:
    with ros_node("sim_nav_test") as (node, executor):
        yield SimClient(node, executor)


# ---------------------------------------------------------------------------- navigation


@pytest.fixture(scope="class")
def nav_sim(tmp_path_factory: pytest.TempPathFactory) -> Iterator[NodeProcess]:
    proc = start_sim(tmp_path_factory.mktemp("nav"), f"speed:={SPEED}")
    try:
        yield proc
    finally:
        proc.stop()


@pytest.fixture
def nav(nav_sim: NodeProcess, client: SimClient) -> SimClient:
    client.wait_ready(nav_sim)
    return client


class TestNavigateToPose:
    def test_goal_to_zone_a_succeeds_with_feedback(self, nav: SimClient) -> None:
        from action_msgs.msg import GoalStatus

        start = nav.robot()
        run = nav.send(*ZONE_A)
        assert run.accepted
        assert run.handle.stamp.sec < 10_000  # accepted at a simulated time, not the epoch
        status, result = nav.finish(run)
        assert status == GoalStatus.STATUS_SUCCEEDED
        assert (result.error_code, result.error_msg) == (0, "")

        fb = run.feedback
        assert len(fb) >= 5
        distances = [f.distance_remaining for f in fb]
        assert distances[0] - distances[-1] > 3.0
        assert all(b <= a + 0.05 for a, b in itertools.pairwise(distances))
        times = [f.navigation_time.sec + f.navigation_time.nanosec * 1e-9 for f in fb]
        assert times == sorted(times) and times[-1] > 5.0  # simulated seconds
        first, last = fb[0].current_pose.pose.position, fb[-1].current_pose.pose.position
        assert math.dist((first.x, first.y), (last.x, last.y)) > 3.0
        assert {f.current_pose.header.frame_id for f in fb} == {"map"}
        assert {f.number_of_recoveries for f in fb} == {0}
        assert fb[0].estimated_time_remaining.sec > fb[-1].estimated_time_remaining.sec

        nav.spin(0.3)  # the latest odometry
        x, y, yaw = nav.robot()
        assert math.hypot(x - ZONE_A[0], y - ZONE_A[1]) <= 0.25, (start, (x, y))
        assert abs(yaw - ZONE_A[2]) <= 0.25

    def test_goal_inside_a_wall_aborts_with_a_reason(self, nav: SimClient) -> None:
        from action_msgs.msg import GoalStatus

        status, result = nav.go(0.0, 3.0, 0.0)  # inside wall_v_top
        assert status == GoalStatus.STATUS_ABORTED
        assert result.error_code == 206  # Jazzy: the planner's ComputePathToPose GOAL_OCCUPIED
        assert result.error_msg == "goal (0.00, 3.00) is inside an obstacle"

    def test_goal_in_another_frame_is_rejected(self, nav: SimClient) -> None:
        run = nav.send(1.0, 0.5, 0.0, frame="odom")
        assert run.handle is not None and not run.accepted

    def test_cancel_midway_stops_the_robot(self, nav: SimClient) -> None:
        from action_msgs.msg import GoalStatus

        run = nav.send(*ZONE_C)
        assert run.accepted
        assert spin_until(
            nav.executor,
            lambda: len(run.feedback) >= 2
            and run.feedback[0].distance_remaining - run.feedback[-1].distance_remaining > 1.0,
            10.0,
        )
        cancel = run.handle.cancel_goal_async()
        assert spin_until(nav.executor, cancel.done, 5.0)
        assert len(cancel.result().goals_canceling) == 1
        status, _ = nav.finish(run)
        assert status == GoalStatus.STATUS_CANCELED

        nav.spin(0.2)
        stopped = nav.robot()
        nav.spin(0.5)  # 15 simulated seconds
        assert nav.robot() == pytest.approx(stopped, abs=1e-3)
        assert nav.odom[-1].twist.twist.linear.x == 0.0
        assert math.hypot(stopped[0] - ZONE_C[0], stopped[1] - ZONE_C[1]) > 0.5

    def test_new_goal_preempts_the_running_one(self, nav: SimClient) -> None:
        from action_msgs.msg import GoalStatus

        first = nav.send(*ZONE_D)
        assert first.accepted
        assert spin_until(nav.executor, lambda: len(first.feedback) >= 3, 10.0)
        second = nav.send(*BASE)
        assert second.accepted
        status, result = nav.finish(first)
        assert status == GoalStatus.STATUS_ABORTED
        assert (result.error_code, result.error_msg) == (0, "")  # Nav2's empty result
        status, _ = nav.finish(second)
        assert status == GoalStatus.STATUS_SUCCEEDED
        nav.spin(0.3)
        x, y, _ = nav.robot()
        assert math.hypot(x, y) <= 0.25


# ---------------------------------------------------------------------------- faults


@pytest.fixture(scope="class")
def reject_sim(tmp_path_factory: pytest.TempPathFactory) -> Iterator[NodeProcess]:
    proc = start_sim(tmp_path_factory.mktemp("reject"), f"speed:={SPEED}",
                     "reject_goals:=true", "accept_delay_wall_s:=1.0")
    try:
        yield proc
    finally:
        proc.stop()


@pytest.fixture(scope="class")
def fault_sim(tmp_path_factory: pytest.TempPathFactory) -> Iterator[NodeProcess]:
    proc = start_sim(
        tmp_path_factory.mktemp("faults"), f"speed:={SPEED}", "abort_goal_numbers:=[2]",
        "abort_delay_s:=0.5", f"blocked_areas:=['{SEAL_ZONE_A_ROOM}']", "speed_scale:=0.5",
    )
    try:
        yield proc
    finally:
        proc.stop()


class TestRejectAndAcceptDelay:
    def test_goals_are_rejected_after_the_acceptance_delay(self, reject_sim: NodeProcess,
                                                           client: SimClient) -> None:
        sim = reject_sim
        client.wait_ready(sim)
        # The answer is held back accept_delay_wall_s (1 s of wall time; how long is not
        # checked here): 30 s is an outer safety bound.
        run = client.send(*ZONE_A, timeout=30.0)
        assert run.handle is not None and not run.accepted
        sim.wait_for_output("injected fault \\(reject_goals\\)", timeout=30)


class TestAbortBlockedAndSlow:
    def test_only_the_second_goal_aborts(self, fault_sim: NodeProcess,
                                         client: SimClient) -> None:
        from action_msgs.msg import GoalStatus

        client.wait_ready(fault_sim)
        outcomes = [client.go(x, y, 0.0) for x, y in ((1.0, 0.8), (0.5, -0.8), (0.0, 0.0))]
        injected = [o for o in outcomes if "injected fault" in o[1].error_msg]
        # Goal numbers count every accepted goal of this simulator, whichever test sent it.
        assert len(injected) == 1
        assert injected[0][0] == GoalStatus.STATUS_ABORTED
        assert "goal 2 aborted" in injected[0][1].error_msg
        others = [o[0] for o in outcomes if o not in injected]
        assert others == [GoalStatus.STATUS_SUCCEEDED] * 2

    def test_blocked_zone_makes_zone_a_unreachable(self, fault_sim: NodeProcess,
                                                   client: SimClient) -> None:
        from action_msgs.msg import GoalStatus

        client.wait_ready(fault_sim)
        status, result = client.go(*ZONE_A)
        assert status == GoalStatus.STATUS_ABORTED
        assert result.error_code == 208  # Jazzy: the planner's ComputePathToPose NO_VALID_PATH
        assert "no path" in result.error_msg

    def test_speed_scale_halves_the_velocity_limits(self, fault_sim: NodeProcess,
                                                    client: SimClient) -> None:
        from action_msgs.msg import GoalStatus

        client.wait_ready(fault_sim)
        first = len(client.odom)
        for target in ((2.0, -1.0, 0.0), (0.0, 0.0, 3.0)):
            status, result = client.go(*target)
            if "injected fault" not in result.error_msg:  # goal 2 of this simulator
                assert status == GoalStatus.STATUS_SUCCEEDED
        speeds = [o.twist.twist.linear.x for o in client.odom[first:]]
        turns = [abs(o.twist.twist.angular.z) for o in client.odom[first:]]
        assert max(speeds) == pytest.approx(0.25, abs=0.01)
        assert max(turns) <= 0.5 + 1e-6


# ---------------------------------------------------------------------------- shutdown


class TestShutdown:
    def test_sigint_aborts_the_goal_flushes_the_trace_and_exits_0(
        self, tmp_path: Path, client: SimClient
    ) -> None:
        from action_msgs.msg import GoalStatus

        from sar_framework.sim.trace import read_trace

        trace_path = tmp_path / "trace.jsonl"
        sim = start_sim(tmp_path, "speed:=5.0", f"trace_file:={trace_path}",
                        "trace_period_s:=0.1")
        try:
            client.wait_ready(sim)
            run = client.send(*ZONE_C)
            assert run.accepted
            assert spin_until(
                client.executor,
                lambda: len(run.feedback) >= 2
                and run.feedback[0].distance_remaining - run.feedback[-1].distance_remaining
                > 1.0,
                15.0,
            )
            sim.send_signal(signal.SIGINT)
            # Outer safety bounds (well under a second expected; benchmarks/bench_mission.py
            # prints how long a stop takes).
            status, result = client.finish(run, timeout=30.0)
            assert status == GoalStatus.STATUS_ABORTED
            assert result.error_msg == "simulator shutting down"
            assert sim.wait(timeout=30.0) == 0, sim.output
        finally:
            sim.stop()

        lines = read_trace(trace_path)
        events = [line for line in lines if "event" in line]
        assert [e["event"] for e in events] == ["start", "accepted", "aborted", "end"]
        accepted, aborted, end = events[1], events[2], events[3]
        assert (accepted["goal"], accepted["x"], accepted["y"]) == (1, 4.0, -3.0)
        assert aborted["error_msg"] == "simulator shutting down"
        poses = [line for line in lines if "event" not in line]
        assert len(poses) >= 10
        assert [p["sim_s"] for p in poses] == sorted(p["sim_s"] for p in poses)
        travelled = sum(
            math.dist((a["x"], a["y"]), (b["x"], b["y"]))
            for a, b in itertools.pairwise(poses)
        )
        assert end["path_m"] == pytest.approx(travelled, abs=0.1)
        assert end["path_m"] > 1.0
