"""Lifecycle state for the simulated Nav2 nodes: ``<node>/get_state`` always answers ACTIVE.

Nav2's servers are lifecycle nodes; ``BasicNavigator.waitUntilNav2Active`` (and our
runner's start-up) polls ``/amcl/get_state`` and ``/bt_navigator/get_state`` until they
report ``active`` (id 3). The simulator's stand-ins are active as soon as they exist.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from lifecycle_msgs.msg import State
from lifecycle_msgs.srv import GetState

if TYPE_CHECKING:
    from rclpy.callback_groups import CallbackGroup
    from rclpy.node import Node
    from rclpy.service import Service


def serve_active_state(node: Node, callback_group: CallbackGroup | None = None) -> Service:
    """Serve ``~/get_state`` on ``node``, answering ``PRIMARY_STATE_ACTIVE`` / ``"active"``.

    Args:
        node: The node (its name gives the service name, e.g. ``/amcl/get_state``).
        callback_group: Group for the service callback.

    Returns:
        The service.
    """

    def answer(_request: GetState.Request, response: GetState.Response) -> GetState.Response:
        response.current_state = State(id=State.PRIMARY_STATE_ACTIVE, label="active")
        return response

    return node.create_service(GetState, "~/get_state", answer, callback_group=callback_group)
