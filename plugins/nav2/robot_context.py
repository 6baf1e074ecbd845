"""What Nav2's robot-aware decorators read, given by the caller in the tree's context (no ROS).

DistanceController, SpeedController and GoalUpdater need the robot's pose, its speed and
goals sent on a topic: ROS things these modules never import. A runner passes them to
``load_tree(context=...)`` as callables (``sar_framework.ros.robot_state`` makes them from
a node: TF, odometry, the ``goal_update`` topic):

- ``ROBOT_POSE_KEY``: ``pose(global_frame, robot_base_frame) -> (x, y) | None``; empty
  frames mean the navigator's defaults;
- ``ROBOT_SPEED_KEY``: ``speed() -> m/s | None`` (planar, from odometry);
- ``GOAL_UPDATE_KEY``: ``update() -> message | None``, the last goal received.

A source may have a ``start()`` method: it is called when a node that reads the source is
built (a runner then subscribes only for trees that need it). Without them the decorators
behave as Nav2's do with no data: no pose (DistanceController
fails), speed 0 (SpeedController ticks at ``min_rate``), no update (GoalUpdater passes
its input goal through).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

ROBOT_POSE_KEY = "robot_pose"
ROBOT_SPEED_KEY = "robot_speed"
GOAL_UPDATE_KEY = "goal_update"

#: ``pose(global_frame, robot_base_frame)``: the robot's (x, y), or None.
PoseSource = Callable[[str, str], "tuple[float, float] | None"]


def _started(context: Mapping[str, Any], key: str) -> Any:
    source = context.get(key)
    start = getattr(source, "start", None)
    if callable(start):
        start()
    return source if callable(source) else None


def pose_source(context: Mapping[str, Any]) -> PoseSource:
    """The context's pose source (started), or one that never knows the pose."""
    return _started(context, ROBOT_POSE_KEY) or (lambda _frame, _base: None)


def speed_source(context: Mapping[str, Any]) -> Callable[[], float | None]:
    """The context's speed source (started), or one that never knows the speed."""
    return _started(context, ROBOT_SPEED_KEY) or (lambda: None)


def update_source(context: Mapping[str, Any]) -> Callable[[], Any]:
    """The context's goal-update source (started), or one that never has an update."""
    return _started(context, GOAL_UPDATE_KEY) or (lambda: None)
