"""Nav2's RemovePassedGoals and TruncatePath: goal lists and paths reshaped on the blackboard.

- RemovePassedGoals drops the goals at the front of ``input_goals`` that the robot is
  within ``radius`` of (from TF), always keeping the last one.
- TruncatePath drops the poses at the end of ``input_path`` closer than ``distance`` to
  its final pose (keeping at least two), and points the new last pose at the old final one.
"""

from __future__ import annotations

import math
from typing import Any

import py_trees
from py_trees.common import Status

from sar_framework.engine.plugin import leaf
from sar_framework.engine.ports import InputPort, OutputPort
from sar_framework.leaves import RosLeaf

from ._common import navigator_setting, optional_input, planar_distance
from ._tf import robot_pose, tf_buffer

PATH = "nav_msgs/msg/Path"


def remove_passed(goals: list[Any], robot: Any, radius: float) -> list[Any]:
    """The goals left once those at the front within ``radius`` of ``robot`` are gone."""
    left = list(goals)
    while len(left) > 1 and planar_distance(left[0], robot) <= radius:
        left.pop(0)
    return left


@leaf(ports=[
    InputPort("radius", float, default=0.5, description="The radius (m) in proximity to the "
              "viapoint for the BT node to remove from the list as having passed."),
    InputPort("global_frame", str, optional=True, description="Reference frame."),
    InputPort("robot_base_frame", str, optional=True, description="Robot base frame. If not "
              "provided, uses the BT Navigator's `robot_base_frame` parameter value."),
    InputPort("input_goals", list, optional=True,
              description="A vector of goals to check if it passed any in the current iteration."),
    OutputPort("output_goals", list,
               description="A vector of goals with goals removed in proximity to the robot."),
])
class RemovePassedGoals(RosLeaf):
    """Nav2's RemovePassedGoals: the via-points the robot has reached leave the list.

    Args:
        name: The behaviour's name.
        ports: The ports above.
    """

    def __init__(self, name: str, *, ports: Any) -> None:
        super().__init__(name)
        self.ports = ports

    def setup(self, **kwargs: Any) -> None:
        """Take the node and start listening to TF."""
        super().setup(**kwargs)
        tf_buffer(self.node)

    def update(self) -> Status:
        """SUCCESS with ``output_goals`` written; FAILURE without a robot pose."""
        goals = list(optional_input(self.ports, "input_goals", []) or [])
        if not goals:
            self.ports.set("output_goals", goals)
            return Status.SUCCESS
        frame = (optional_input(self.ports, "global_frame")
                 or navigator_setting(self._node, "global_frame"))
        base = (optional_input(self.ports, "robot_base_frame")
                or navigator_setting(self._node, "robot_base_frame"))
        robot = robot_pose(self.node, frame, base)
        if robot is None:
            self.feedback_message = f"no robot pose ({frame} -> {base})"
            return Status.FAILURE
        left = remove_passed(goals, robot, float(self.ports.get("radius")))
        self.ports.set("output_goals", left)
        self.feedback_message = f"{len(goals) - len(left)} passed, {len(left)} left"
        return Status.SUCCESS


def truncate(path: Any, distance: float) -> Any:
    """A copy of ``path`` without its poses closer than ``distance`` to its final pose.

    At least two poses stay; the new last pose faces the old final pose.

    Raises:
        ValueError: The heading to the final pose is not a number.
    """
    from geometry_msgs.msg import PoseStamped
    from nav_msgs.msg import Path

    out = Path(header=path.header, poses=list(path.poses))
    if not out.poses:
        return out
    final = out.poses[-1]
    while len(out.poses) > 2 and planar_distance(out.poses[-1], final) < distance:
        out.poses.pop()
    last = out.poses[-1]
    angle = math.atan2(final.pose.position.y - last.pose.position.y,
                       final.pose.position.x - last.pose.position.x)
    if not math.isfinite(angle):
        raise ValueError("the truncated path's final heading is not a number")
    turned = PoseStamped(header=last.header)
    turned.pose.position = last.pose.position
    turned.pose.orientation.z, turned.pose.orientation.w = math.sin(angle / 2), math.cos(angle / 2)
    out.poses[-1] = turned
    return out


@leaf(ports=[
    InputPort("input_path", PATH, optional=True, description="The original path to be truncated."),
    InputPort("distance", float, default=1.0,
              description="The distance to the original goal for truncating the path."),
    OutputPort("output_path", PATH, description="The resulting truncated path."),
])
class TruncatePath(py_trees.behaviour.Behaviour):
    """Nav2's TruncatePath: a path that stops ``distance`` short of its goal.

    Args:
        name: The behaviour's name.
        ports: The ports above.
    """

    def __init__(self, name: str, *, ports: Any) -> None:
        super().__init__(name=name)
        self.ports = ports

    def update(self) -> Status:
        """SUCCESS with ``output_path`` written; FAILURE without an input path."""
        path = optional_input(self.ports, "input_path")
        if path is None:
            self.feedback_message = "no input_path"
            return Status.FAILURE
        try:
            out = truncate(path, float(self.ports.get("distance")))
        except ValueError as exc:
            self.feedback_message = str(exc)
            return Status.FAILURE
        self.ports.set("output_path", out)
        self.feedback_message = f"{len(path.poses)} -> {len(out.poses)} poses"
        return Status.SUCCESS
