"""Nav2's planner, smoother and controller clients.

ComputePathToPose, ComputePathThroughPoses, SmoothPath, FollowPath.

Each is a :class:`~._bt_nodes.Nav2ActionLeaf` with Nav2's ports (nav2_tree_nodes.xml) and
Nav2 Jazzy's semantics: a path output is cleared (an empty ``nav_msgs/Path``) when the
planner fails or is cancelled; ``error_code_id`` is 0 (NONE) on success and the server's
code on failure; FollowPath sends its goal again when ``path`` or an id port changes while
it runs (Nav2's preemption by a new path).
"""

from __future__ import annotations

from typing import Any

from py_trees.common import Status

from sar_framework.engine.plugin import leaf
from sar_framework.engine.ports import InputPort, OutputPort

from ._bt_nodes import Nav2ActionLeaf
from ._common import duration_msg, optional_input, server_ports

POSE = "geometry_msgs/msg/PoseStamped"
PATH = "nav_msgs/msg/Path"
ERROR_CODE = OutputPort("error_code_id", int,
                        description="The server's error code (0, NONE, when it succeeded).")


def fill_start(leaf: Nav2ActionLeaf) -> None:
    """A planner's optional ``start`` (and ``use_start``) into its goal."""
    start = optional_input(leaf.ports, "start")
    if start is not None:
        leaf.goal.start = start
        leaf.goal.use_start = bool(optional_input(leaf.ports, "use_start", True))


@leaf(ports=[
    InputPort("start", POSE, optional=True, description="Start pose. Optional. Used as the "
              "planner start pose instead of the current robot pose, if `use_start` is not "
              "false (i.e. not provided or set to true)."),
    InputPort("use_start", bool, optional=True,
              description="Optional. For using or not using (i.e. ignoring) the provided "
                          "start pose `start`."),
    InputPort("goal", POSE, optional=True, description="Goal pose."),
    InputPort("planner_id", str, default="",
              description="Mapped name to the planner plugin type to use, e.g. GridBased."),
    *server_ports("compute_path_to_pose"),
    OutputPort("path", PATH, description="Path created by action server."),
    ERROR_CODE,
])
class ComputePathToPose(Nav2ActionLeaf):
    """Nav2's ComputePathToPose: a path from the robot (or ``start``) to ``goal``."""

    action_type = "nav2_msgs/action/ComputePathToPose"
    SERVER = "compute_path_to_pose"
    PATH_OUTPUT = "path"

    def on_tick(self) -> bool:
        """Fill the goal from the ports (False: fail without sending)."""
        goal = optional_input(self.ports, "goal")
        if goal is None:
            self.feedback_message = "ComputePathToPose: no goal"
            return False
        self.goal.goal = goal
        self.goal.planner_id = optional_input(self.ports, "planner_id", "")
        fill_start(self)
        return True


@leaf(ports=[
    InputPort("start", POSE, optional=True, description="Start pose. Optional. Only used "
              "if not left empty."),
    InputPort("goals", list, optional=True, description="Goal poses."),
    InputPort("planner_id", str, default="",
              description="Mapped name to the planner plugin type to use, e.g. GridBased."),
    *server_ports("compute_path_through_poses"),
    OutputPort("path", PATH, description="Path created by action server."),
    ERROR_CODE,
])
class ComputePathThroughPoses(Nav2ActionLeaf):
    """Nav2's ComputePathThroughPoses: a path through every pose of ``goals``, in order."""

    action_type = "nav2_msgs/action/ComputePathThroughPoses"
    SERVER = "compute_path_through_poses"
    PATH_OUTPUT = "path"

    def on_tick(self) -> bool:
        """Fill the goal from the ports (False: fail without sending)."""
        goals = optional_input(self.ports, "goals")
        if not goals:
            self.feedback_message = "ComputePathThroughPoses: no goals"
            return False
        self.goal.goals = list(goals)
        self.goal.planner_id = optional_input(self.ports, "planner_id", "")
        fill_start(self)
        return True


@leaf(ports=[
    InputPort("unsmoothed_path", PATH, optional=True, description="The path to smooth."),
    InputPort("max_smoothing_duration", float, default=3.0,
              description="Maximum time to smooth for (seconds)."),
    InputPort("check_for_collisions", bool, default=False,
              description="Whether to check the output smoothed path for collisions."),
    InputPort("smoother_id", str, optional=True,
              description="The smoother plugin ID to use for smoothing in the smoother server."),
    *server_ports("smooth_path"),
    OutputPort("smoothed_path", PATH, description="The smoothed path."),
    OutputPort("smoothing_duration", float, description="The actual duration used for smoothing."),
    OutputPort("was_completed", bool, description="Whether the smoothing process was completed."),
    ERROR_CODE,
])
class SmoothPath(Nav2ActionLeaf):
    """Nav2's SmoothPath: the smoother server's version of ``unsmoothed_path``."""

    action_type = "nav2_msgs/action/SmoothPath"
    SERVER = "smooth_path"

    def on_tick(self) -> bool:
        """Fill the goal from the ports (False: fail without sending)."""
        path = optional_input(self.ports, "unsmoothed_path")
        if path is None:
            self.feedback_message = "SmoothPath: no unsmoothed_path"
            return False
        self.goal.path = path
        self.goal.smoother_id = optional_input(self.ports, "smoother_id", "") or ""
        self.goal.max_smoothing_duration = duration_msg(
            float(optional_input(self.ports, "max_smoothing_duration", 3.0)))
        self.goal.check_for_collisions = bool(
            optional_input(self.ports, "check_for_collisions", False))
        return True

    def on_success(self) -> Status:
        """Write the outputs of a success."""
        result = self.result
        self.ports.set("smoothed_path", result.path)
        duration = result.smoothing_duration
        self.ports.set("smoothing_duration", duration.sec + duration.nanosec / 1e9)
        self.ports.set("was_completed", bool(result.was_completed))
        self.set_error_code(0)
        return Status.SUCCESS


@leaf(ports=[
    InputPort("path", PATH, optional=True, description="The path to follow."),
    InputPort("controller_id", str, optional=True, description="Mapped name of the controller "
              "plugin type to use, e.g. FollowPath."),
    InputPort("goal_checker_id", str, optional=True, description="Mapped name of the goal "
              "checker plugin type to use, e.g. SimpleGoalChecker."),
    InputPort("progress_checker_id", str, optional=True, description="Mapped name of the "
              "progress checker plugin type to use, e.g. SimpleProgressChecker."),
    *server_ports("follow_path"),
    ERROR_CODE,
])
class FollowPath(Nav2ActionLeaf):
    """Nav2's FollowPath: the controller drives ``path``; a new path while it runs is sent."""

    action_type = "nav2_msgs/action/FollowPath"
    SERVER = "follow_path"
    IDS = ("controller_id", "goal_checker_id", "progress_checker_id")

    def on_tick(self) -> bool:
        """Fill the goal from the ports (False: fail without sending)."""
        path = optional_input(self.ports, "path")
        if path is None:
            self.feedback_message = "FollowPath: no path"
            return False
        self.goal.path = path
        for name in self.IDS:
            setattr(self.goal, name, optional_input(self.ports, name, "") or "")
        return True

    def on_wait_for_result(self, feedback: Any) -> None:
        """Send the goal again when the path or an id changed (Nav2's preemption)."""
        path = optional_input(self.ports, "path")
        if (path is not None and path is not self.goal.path and path.poses
                and path != self.goal.path):
            self.goal.path = path
            self.goal_updated = True
        for name in self.IDS:
            value = optional_input(self.ports, name, "") or ""
            if value != getattr(self.goal, name):
                setattr(self.goal, name, value)
                self.goal_updated = True
