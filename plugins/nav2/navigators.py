"""Nav2's navigator clients and CancelControl: NavigateToPose, NavigateThroughPoses.

A tree can hand a whole navigation to a ``bt_navigator`` (Nav2's or the simulator's) with
these, and CancelControl cancels every goal of the controller server (``follow_path``).
"""

from __future__ import annotations

from typing import Any

from py_trees.common import Status

from sar_framework.engine.plugin import leaf
from sar_framework.engine.ports import InputPort, OutputPort

from ._bt_nodes import Nav2ActionLeaf, Nav2ServiceLeaf
from ._common import optional_input, server_ports

_TREE = ("Behavior tree absolute path. If none is specified, the action server uses a "
         "default behavior tree.")
_ERROR = OutputPort("error_code_id", int, description="The navigator's error code (0, NONE, "
                                                      "when it succeeded).")


@leaf(ports=[
    InputPort("goal", "geometry_msgs/msg/PoseStamped", optional=True,
              description="The goal, e.g. \"{goal}\"."),
    InputPort("behavior_tree", str, optional=True, description=_TREE),
    *server_ports("navigate_to_pose"),
    _ERROR,
])
class NavigateToPose(Nav2ActionLeaf):
    """Nav2's NavigateToPose: the navigator drives to ``goal``."""

    action_type = "nav2_msgs/action/NavigateToPose"
    SERVER = "navigate_to_pose"

    def on_tick(self) -> bool:
        """Fill the goal from the ports (False: fail without sending)."""
        goal = optional_input(self.ports, "goal")
        if goal is None:
            self.feedback_message = "NavigateToPose: no goal"
            return False
        self.goal.pose = goal
        self.goal.behavior_tree = optional_input(self.ports, "behavior_tree", "") or ""
        return True


@leaf(ports=[
    InputPort("goals", list, optional=True, description="Goal poses, e.g. \"{goals}\"."),
    InputPort("behavior_tree", str, optional=True, description=_TREE),
    *server_ports("navigate_through_poses"),
    _ERROR,
])
class NavigateThroughPoses(Nav2ActionLeaf):
    """Nav2's NavigateThroughPoses: the navigator drives through every pose of ``goals``."""

    action_type = "nav2_msgs/action/NavigateThroughPoses"
    SERVER = "navigate_through_poses"

    def on_tick(self) -> bool:
        """Fill the goal from the ports (False: fail without sending)."""
        goals = optional_input(self.ports, "goals")
        if not goals:
            self.feedback_message = "NavigateThroughPoses: no goals"
            return False
        self.goal.poses = list(goals)
        self.goal.behavior_tree = optional_input(self.ports, "behavior_tree", "") or ""
        return True


@leaf(ports=server_ports("follow_path"))
class CancelControl(Nav2ServiceLeaf):
    """Nav2's CancelControl: cancel every goal of the controller server, then SUCCESS.

    As Nav2's ``BtCancelActionNode``: the cancel request (all goals: a zero goal id and
    stamp) goes to the action's cancel service; the leaf succeeds when it is answered, and
    also, with an error logged, when no answer came within ``server_timeout``.

    Args:
        name: The behaviour's name.
        ports: ``server_name`` (``follow_path``), ``server_timeout``.
    """

    service_type = "action_msgs/srv/CancelGoal"
    SERVER = "follow_path"

    def service_from_ports(self) -> str:
        """The cancel service of the ``server_name`` action."""
        server = optional_input(self.ports, "server_name") or self.SERVER
        return f"{server.rstrip('/')}/_action/cancel_goal"

    def on_response(self, response: Any) -> Status:
        """Every goal is cancelled."""
        return self.succeed(f"goals of {self._server()} cancelled")

    def on_failure(self, reason: str) -> Status:
        """No answer: SUCCESS all the same, with an error logged (as Nav2)."""
        self.node.get_logger().error(f"Failed to cancel action server for {self._server()}")
        return self.succeed(f"no answer from {self._server()} to the cancel request")

    def _server(self) -> str:
        return self.service_name.removesuffix("/_action/cancel_goal")
