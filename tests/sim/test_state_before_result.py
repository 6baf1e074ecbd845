"""A motion goal's result never reaches a client before the ``/tf`` that shows its end.

Nav2's behaviours and controller judge a goal done from TF, so by the time a client gets
SUCCEEDED, TF already holds the pose that made it so. The simulator's physics thread
publishes the state at ``publish_hz`` while an executor thread sends the result: unordered,
a client that read TF on the result saw the pose from before the goal (a spin of 1.57 rad
read as 0.0 on a loaded machine). With ``publish_hz`` low the gap is long: the next state
comes up to 1 s wall after the result, far beyond the 0.3 s the test lets the client's
queue drain.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

import pytest
from sar_testing.processes import NodeProcess
from sar_testing.spin import ros_node, spin_until

from sar_framework.testing.sim_control import sim_process

pytestmark = [pytest.mark.ros, pytest.mark.timeout(120)]
pytest.importorskip("nav2_msgs.action", reason="needs the full nav2_msgs")


@pytest.fixture(scope="module")
def sim(tmp_path_factory: pytest.TempPathFactory) -> Iterator[NodeProcess]:
    # /tf once per 5 simulated seconds; a 1.57 rad spin takes about 1.6 s
    with sim_process(tmp_path_factory.mktemp("sim"), "publish_hz:=0.2", speed=5.0) as proc:
        yield proc


def yaw(node: Any) -> float | None:
    from sar_plugins.nav2._common import yaw_of
    from sar_plugins.nav2._tf import robot_pose

    pose = robot_pose(node, "map", "base_link")
    return None if pose is None else yaw_of(pose.pose.orientation)


def test_tf_shows_a_spin_when_its_result_arrives(sim: NodeProcess) -> None:
    from nav2_msgs.action import Spin
    from rclpy.action import ActionClient

    with ros_node("state_before_result_test") as (node, executor):
        client = ActionClient(node, Spin, "spin")
        assert spin_until(executor, client.server_is_ready, 15.0), sim.output
        assert spin_until(executor, lambda: yaw(node) is not None, 15.0)
        before = yaw(node)
        sent = client.send_goal_async(Spin.Goal(target_yaw=1.57))
        assert spin_until(executor, sent.done, 10.0)
        result = sent.result().get_result_async()
        assert spin_until(executor, result.done, 30.0), sim.output
        assert result.result().status == 4  # GoalStatus.STATUS_SUCCEEDED

        def turned() -> float:
            return math.remainder(yaw(node) - before, math.tau)

        # The /tf the simulator sent before the result may still sit in this process's
        # queue (a loaded client takes one message per spin): let it drain, for much less
        # than the 1 s wall (5 s simulated) until the next state would be published.
        spin_until(executor, lambda: abs(turned() - 1.57) <= 0.15, 0.3)
        assert turned() == pytest.approx(1.57, abs=0.15)
