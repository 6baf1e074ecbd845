"""Nav2's lifecycle and live localisation on any tier (lifecycle_msgs only, over real DDS).

Before: each stand-in served only ``get_state`` (``ros2 lifecycle list /amcl`` and
``ros2 lifecycle set ... deactivate`` hung), ``/map`` came from the simulator node, and
``/amcl_pose`` was published only in answer to ``/initialpose`` (still (0, 0) after driving).
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

import pytest
from sar_testing.processes import NodeProcess
from sar_testing.spin import call_service, ros_node, spin_until

pytestmark = pytest.mark.ros
DISCOVERY_S = 15.0
NAV2_NODES = ("map_server", "amcl", "controller_server", "smoother_server", "planner_server",
              "behavior_server", "bt_navigator", "waypoint_follower")


@pytest.fixture(scope="module")
def sim(tmp_path_factory: pytest.TempPathFactory) -> Iterator[NodeProcess]:
    args = ["-m", "sar_framework.sim", "--ros-args", "-p", "speed:=20.0"]
    with NodeProcess(args, "sim", log_dir=tmp_path_factory.mktemp("sim")) as proc:
        proc.wait_for_output("ready", timeout=30)
        yield proc


@pytest.fixture(scope="module")
def client() -> Iterator[tuple]:
    with ros_node("sim_lifecycle_test") as pair:
        yield pair


def call(client: tuple, srv_type: Any, name: str, request: Any, *, repeatable: bool = True) -> Any:
    node, executor = client
    return call_service(node, executor, srv_type, name, request, discovery_timeout=DISCOVERY_S,
                        resend_after=2.0 if repeatable else None)


def change_state(client: tuple, node_name: str, transition_id: int) -> bool:
    from lifecycle_msgs.srv import ChangeState

    request = ChangeState.Request()
    request.transition.id = transition_id
    return call(client, ChangeState, f"/{node_name}/change_state", request,
                repeatable=False).success


def state_label(client: tuple, node_name: str) -> str:
    from lifecycle_msgs.srv import GetState

    return call(client, GetState, f"/{node_name}/get_state", GetState.Request()
                ).current_state.label


def send_goal(client: tuple, x: float, y: float) -> Any:
    """Send a navigate_to_pose goal; return its handle (check ``.accepted``)."""
    from nav2_msgs.action import NavigateToPose
    from rclpy.action import ActionClient

    node, executor = client
    action = ActionClient(node, NavigateToPose, "navigate_to_pose")
    assert spin_until(executor, action.server_is_ready, DISCOVERY_S)
    goal = NavigateToPose.Goal()
    goal.pose.header.frame_id = "map"
    goal.pose.pose.position.x, goal.pose.pose.position.y = x, y
    goal.pose.pose.orientation.w = 1.0
    sent = action.send_goal_async(goal)
    assert spin_until(executor, sent.done, 10.0)
    return sent.result()


@pytest.mark.usefixtures("sim")
class TestLifecycle:
    @pytest.mark.parametrize("name", NAV2_NODES)
    def test_every_nav2_node_is_an_active_lifecycle_node(self, client: tuple,
                                                         name: str) -> None:
        from lifecycle_msgs.srv import GetAvailableTransitions

        assert state_label(client, name) == "active"
        answer = call(client, GetAvailableTransitions, f"/{name}/get_available_transitions",
                      GetAvailableTransitions.Request())  # what `ros2 lifecycle list` asks
        labels = {t.transition.label for t in answer.available_transitions}
        assert {"deactivate", "shutdown"} <= labels

    def test_map_comes_from_map_server_latched(self, client: tuple) -> None:
        from rclpy.qos import DurabilityPolicy

        node, executor = client

        def known() -> bool:  # the graph may name a fresh endpoint's node only later
            found = node.get_publishers_info_by_topic("/map")
            return bool(found) and found[0].node_name != "_NODE_NAME_UNKNOWN_"

        assert spin_until(executor, known, DISCOVERY_S)
        (publisher,) = node.get_publishers_info_by_topic("/map")
        assert publisher.node_name == "map_server"
        assert publisher.qos_profile.durability == DurabilityPolicy.TRANSIENT_LOCAL

    def test_deactivated_bt_navigator_refuses_goals_until_reactivated(self,
                                                                     client: tuple) -> None:
        from lifecycle_msgs.msg import Transition, TransitionEvent

        node, executor = client
        events: list[TransitionEvent] = []
        node.create_subscription(TransitionEvent, "/bt_navigator/transition_event",
                                 events.append, 10)
        spin_until(executor, lambda: False, 0.5)
        assert change_state(client, "bt_navigator", Transition.TRANSITION_DEACTIVATE)
        assert state_label(client, "bt_navigator") == "inactive"
        assert spin_until(executor, lambda: any(e.goal_state.label == "inactive"
                                                for e in events), 5.0)
        assert not send_goal(client, 0.5, 0.0).accepted
        assert change_state(client, "bt_navigator", Transition.TRANSITION_ACTIVATE)
        handle = send_goal(client, 0.5, 0.0)
        assert handle.accepted
        handle.cancel_goal_async()
        spin_until(executor, lambda: False, 0.5)

    def test_amcl_pose_follows_the_robot(self, client: tuple) -> None:
        from action_msgs.msg import GoalStatus
        from geometry_msgs.msg import PoseWithCovarianceStamped

        from sar_framework.ros.qos import latched_qos

        node, executor = client
        poses: list[PoseWithCovarianceStamped] = []
        node.create_subscription(PoseWithCovarianceStamped, "/amcl_pose", poses.append,
                                 latched_qos())
        handle = send_goal(client, 1.0, 0.5)
        assert handle.accepted
        result = handle.get_result_async()
        assert spin_until(executor, result.done, 30.0)
        assert result.result().status == GoalStatus.STATUS_SUCCEEDED
        spin_until(executor, lambda: False, 1.0)
        assert len(poses) >= 3  # one update per 0.25 m travelled (update_min_d)
        last = poses[-1].pose
        assert math.hypot(last.pose.position.x - 1.0, last.pose.position.y - 0.5) < 0.3
        assert 0.0 < last.covariance[0] < 0.25 and last.covariance[35] > 0.0
