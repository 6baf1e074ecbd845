"""The shared objects a tree is built with, by the runner: at start-up and at each reload.

``load_tree(tree, context=tree_context(mission, node))``: the mission's ZoneManager, the
node's clock (timeouts count ROS time) and the robot's state (:mod:`sar_framework.ros.robot_state`).
A reload (:mod:`.reload`) builds its new leaves with the same objects, so the mission's
shared state (zones visited, survivors) is never lost.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from rclpy.node import Node

    from sar_framework.mission.params import MissionParams


def tree_context(mission: MissionParams, node: Node) -> dict[str, Any]:
    """The tree's shared objects: the ZoneManager, the node's clock, the robot's state.

    Args:
        mission: The mission parameters (their ZoneManager).
        node: The runner node (its clock; the robot's state it subscribes to).

    Returns:
        The context, by the names plugins declare.
    """
    from sar_framework.engine.building.control_build import CLOCK_KEY
    from sar_framework.ros.robot_state import robot_context

    clock = node.get_clock()

    def now() -> float:
        return clock.now().nanoseconds / 1e9

    return {"zone_manager": mission.zone_manager, CLOCK_KEY: now, **robot_context(node)}
