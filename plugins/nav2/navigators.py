"""Nav2's navigator clients and CancelControl: NavigateToPose, NavigateThroughPoses.

A tree can hand a whole navigation to a ``bt_navigator`` (Nav2's or the simulator's) with
these, and CancelControl cancels every goal of the controller server (``follow_path``).
"""

from __future__ import annotations

import time
from typing import Any

from py_trees.common import Status

from sar_framework.engine.plugin import leaf
from sar_framework.engine.ports import InputPort, OutputPort
from sar_framework.leaves import RosLeaf

from ._bt_nodes import Nav2ActionLeaf
from ._common import optional_input, server_ports, server_timeout_s

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
class CancelControl(RosLeaf):
    """Nav2's CancelControl: cancel every goal of the controller server, then SUCCESS.

    As Nav2's ``BtCancelActionNode``: the cancel request (all goals) is sent on the first
    tick; the leaf succeeds when it is answered, and also, with an error logged, when no
    answer came within ``server_timeout``.

    Args:
        name: The behaviour's name.
        ports: ``server_name`` (``follow_path``), ``server_timeout``.
    """

    def __init__(self, name: str, *, ports: Any) -> None:
        super().__init__(name)
        self.ports = ports
        self.server_name = "follow_path"
        self._client: Any = None
        self._future: Any = None
        self._sent = 0.0

    def setup(self, **kwargs: Any) -> None:
        """Take the node; a client of the action's cancel service (cancel all goals)."""
        super().setup(**kwargs)
        from action_msgs.srv import CancelGoal

        self.server_name = optional_input(self.ports, "server_name") or "follow_path"
        self._client = self.node.create_client(
            CancelGoal, f"{self.server_name.rstrip('/')}/_action/cancel_goal")

    def initialise(self) -> None:
        """Send the cancel-all request (a zero goal id and stamp)."""
        from action_msgs.srv import CancelGoal

        self.reset_latch()
        self._future = self._client.call_async(CancelGoal.Request())
        self._sent = time.monotonic()

    def update(self) -> Status:
        """SUCCESS once answered, or once ``server_timeout`` passed (logged as an error)."""
        if self._done:
            return self.verdict()
        if self._future.done():
            return self.latch(True, f"goals of {self.server_name} cancelled")
        if time.monotonic() - self._sent < server_timeout_s(self._node, self.ports):
            return Status.RUNNING
        self._future.cancel()
        self.node.get_logger().error(f"Failed to cancel action server for {self.server_name}")
        return self.latch(True, f"no answer from {self.server_name} to the cancel request",
                           log=False)

    def shutdown(self) -> None:
        """Destroy the client."""
        if self._client is not None:
            self.node.destroy_client(self._client)
            self._client = None
