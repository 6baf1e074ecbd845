"""After the mission, ``ros2 topic echo /tf_static --once`` shows every survivor, on both tiers.

``--once`` prints the first message a late subscriber gets. With the stand-in broadcaster at
depth 100 that was the first of all past messages, holding only survivor_1; tf2_ros's
broadcaster keeps one message with every frame. Where the ros2 CLI is installed it is run
itself; elsewhere an rclpy subscriber with the QoS ``ros2 topic echo`` picks stands in.
"""

from __future__ import annotations

import signal
from collections.abc import Iterator

import pytest
from e2e.helpers import DEFAULT_TREE, sar_tree_run
from sar_testing.processes import NodeProcess
from sar_testing.ros2_cli import ros2_executable, run_ros2
from sar_testing.spin import ros_node, spin_until

pytestmark = [pytest.mark.slow, pytest.mark.ros]


@pytest.fixture(scope="module")
def mission(tmp_path_factory: pytest.TempPathFactory) -> Iterator[NodeProcess]:
    """The default mission, staying up after it ends (``--keep-alive``)."""
    process = sar_tree_run([str(DEFAULT_TREE), "--keep-alive"],
                           tmp_path_factory.mktemp("mission") / "report")
    try:
        process.wait_for_output(r"Staying up \(--keep-alive\)", timeout=90)
        yield process
        process.send_signal(signal.SIGINT)
        process.wait(timeout=10)
    finally:
        process.stop()


def first_message_frames() -> list[str]:
    """The child frames of the first /tf_static message a late ``echo``-like subscriber gets."""
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
    from tf2_msgs.msg import TFMessage

    qos = QoSProfile(depth=5, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)  # sensor_data, adapted
    with ros_node("tf_static_echo_once") as (node, executor):
        messages: list[TFMessage] = []
        node.create_subscription(TFMessage, "/tf_static", messages.append, qos)
        assert spin_until(executor, lambda: bool(messages), 15.0), "no /tf_static message"
        return [t.child_frame_id for t in messages[0].transforms]


def test_echo_once_shows_every_survivor(mission: NodeProcess) -> None:
    if ros2_executable() is not None:
        echoed = run_ros2("topic", "echo", "/tf_static", "--once")
        frames = [line.split(":", 1)[1].strip() for line in echoed.splitlines()
                  if line.strip().startswith("child_frame_id:")]
    else:
        frames = first_message_frames()
    assert {"survivor_1", "survivor_2"} <= set(frames), mission.output[-2000:]
