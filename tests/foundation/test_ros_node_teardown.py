"""The tests' ``ros_node`` leaves nothing of its node in the graph once its block ends."""

from __future__ import annotations

import pytest

from sar_framework.testing.spin import ros_node

pytestmark = pytest.mark.ros


def test_action_clients_and_servers_are_destroyed_with_the_block() -> None:
    from nav2_msgs.action import Spin
    from rclpy.action import ActionClient, ActionServer
    from rclpy.exceptions import InvalidHandle

    with ros_node("teardown_probe") as (node, _):
        client = ActionClient(node, Spin, "probe_action")
        server = ActionServer(node, Spin, "probe_action", lambda goal: Spin.Result())
    # a live one keeps the node, and its DDS participant, in the graph the next test sees
    for handle in (client._client_handle, server._handle):
        with pytest.raises(InvalidHandle), handle:
            pass
