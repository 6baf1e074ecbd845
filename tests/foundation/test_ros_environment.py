"""Smoke tests that prove the ROS 2 environment for real: two processes, real DDS.

- a DetectSurvivor service call between processes;
- a NavigateToPose goal with feedback, then a cancel the server sees;
- a /tf_static message received by a subscriber that starts after it was sent.
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import pytest
from sar_testing.processes import NodeProcess
from sar_testing.spin import call_service, spin_until

pytestmark = pytest.mark.ros
NODES = Path(__file__).resolve().parent.parent / "sar_testing" / "nodes"
DISCOVERY_S = 15.0  # discovery across processes takes ~3 s; leave room on a loaded machine


def test_run_is_isolated_on_loopback_and_own_domain() -> None:
    assert os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] == "LOCALHOST"
    assert 1 <= int(os.environ["ROS_DOMAIN_ID"]) <= 101


def test_each_xdist_worker_leases_a_domain_of_its_own(tmp_path: Path) -> None:
    pytest.importorskip("xdist", reason="pytest-xdist is not installed")
    probe = Path(__file__).with_name("xdist_probe.py")
    done = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-n", "2", str(probe)],
        cwd=probe.parents[2], capture_output=True, text=True, timeout=120, check=False,
        env={**os.environ, "SAR_XDIST_PROBE_DIR": str(tmp_path)})
    assert done.returncode == 0, done.stdout + done.stderr
    seen = {tuple(f.read_text().split()) for f in tmp_path.glob("*.txt")}
    by_worker = dict(seen)
    assert sorted(by_worker) == ["gw0", "gw1"], seen
    assert len(set(by_worker.values())) == 2, seen  # one domain per worker
    assert len(seen) == 2, seen  # and each worker kept its own all along


def test_detect_survivor_call_between_processes(ros: tuple, tmp_path: Path) -> None:
    from sar_interfaces.srv import DetectSurvivor

    node, executor = ros
    with NodeProcess([str(NODES / "detect_echo_server.py")], "detect", log_dir=tmp_path) as srv:
        srv.wait_for_output("ready")
        found = call_service(node, executor, DetectSurvivor, "/detect_survivor",
                             DetectSurvivor.Request(zone_id="zone_a"),
                             discovery_timeout=DISCOVERY_S)
        assert found.found is True
        assert (found.survivor_x, found.survivor_y) == (1.5, -2.0)

        empty = call_service(node, executor, DetectSurvivor, "/detect_survivor",
                             DetectSurvivor.Request(zone_id="zone_b"))
        assert empty.found is False
        srv.wait_for_output("asked about zone_b")


def test_navigate_to_pose_feedback_and_cancel_between_processes(ros: tuple,
                                                                tmp_path: Path) -> None:
    from action_msgs.msg import GoalStatus
    from nav2_msgs.action import NavigateToPose
    from rclpy.action import ActionClient

    node, executor = ros
    with NodeProcess([str(NODES / "slow_navigate_server.py")], "nav", log_dir=tmp_path) as srv:
        srv.wait_for_output("ready")
        client = ActionClient(node, NavigateToPose, "navigate_to_pose")
        assert spin_until(executor, client.server_is_ready, DISCOVERY_S), srv.output

        feedback: list[float] = []
        goal = NavigateToPose.Goal()
        goal.pose.header.frame_id = "map"
        goal.pose.pose.position.x = 2.0
        sent = client.send_goal_async(
            goal, feedback_callback=lambda msg: feedback.append(msg.feedback.distance_remaining)
        )
        assert spin_until(executor, sent.done, 5.0)
        handle = sent.result()
        assert handle.accepted

        assert spin_until(executor, lambda: len(feedback) >= 3, 5.0)
        assert feedback[0] > feedback[-1], "distance_remaining should shrink"

        cancel = handle.cancel_goal_async()
        assert spin_until(executor, cancel.done, 5.0)
        assert len(cancel.result().goals_canceling) == 1
        result = handle.get_result_async()
        assert spin_until(executor, result.done, 5.0)
        assert result.result().status == GoalStatus.STATUS_CANCELED
        srv.wait_for_output("goal canceled")


def test_tf_static_reaches_a_subscriber_that_joins_later(ros: tuple, tmp_path: Path) -> None:
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
    from tf2_msgs.msg import TFMessage

    node, executor = ros
    with NodeProcess([str(NODES / "static_frame_publisher.py")], "tf", log_dir=tmp_path) as pub:
        pub.wait_for_output("sent")
        time.sleep(1.0)  # the message is well gone before anyone listens
        received: list[TFMessage] = []
        qos = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL)
        node.create_subscription(TFMessage, "/tf_static", received.append, qos)
        assert spin_until(executor, lambda: bool(received), DISCOVERY_S), pub.output
        frame = received[0].transforms[0]
        assert (frame.header.frame_id, frame.child_frame_id) == ("map", "smoke_frame")
        assert frame.transform.translation.x == 1.25
