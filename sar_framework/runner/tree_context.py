"""The shared objects a tree is built with, by the runner: at start-up and at each reload.

``load_tree(tree, context=tree_context(node, apps))``: the node's clock (timeouts count ROS
time), the robot's state (:mod:`sar_framework.ros.robot_state`) and each app's context
objects (:attr:`~sar_framework.app.AppRun.context`). A reload (:mod:`.reload`) builds its new
leaves with the same objects, so the mission's shared state is never lost.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from rclpy.node import Node

    from sar_framework.app import AppRun


def tree_context(node: Node, apps: Sequence[AppRun] = ()) -> dict[str, Any]:
    """The tree's shared objects: the node's clock, the robot's state, the apps' objects.

    Args:
        node: The runner node (its clock; the robot's state it subscribes to).
        apps: The tree's apps, started (their context objects).

    Returns:
        The context, by the names plugins declare.
    """
    from sar_framework.engine.building.control_build import CLOCK_KEY
    from sar_framework.ros.robot_state import robot_context

    clock = node.get_clock()

    def now() -> float:
        return clock.now().nanoseconds / 1e9

    context: dict[str, Any] = {CLOCK_KEY: now, **robot_context(node)}
    for app in apps:
        context.update(app.context)
    return context
