"""The costmap nodes' services and the planner server's ``is_path_valid``.

``/global_costmap/global_costmap`` (owned by ``planner_server``) and
``/local_costmap/local_costmap`` (owned by ``controller_server``) each serve Nav2's three
clearing services, by Nav2's names:

- ``clear_entirely_<costmap>`` (ClearEntireCostmap): every phantom of that costmap goes;
- ``clear_around_<costmap>`` (ClearCostmapAroundRobot): the phantoms centred in the square of
  side ``reset_distance`` around the robot go;
- ``clear_except_<costmap>`` (ClearCostmapExceptRegion): the phantoms centred outside it go.

What a costmap holds is described in :mod:`~sar_framework.sim.costmaps`: the static map and
``blocked_areas`` never clear. ``is_path_valid`` (IsPathValid) checks a path's poses, from the
one nearest the robot on, against the global costmap (map, blocked areas, its phantoms):
a pose in a lethal cell (or off the map) is invalid. Nav2 Jazzy also rejects inscribed cells
(within the robot's radius of an obstacle); the simulator does not, since its spawn lies
that close to a wall and every path from it would be invalid.
"""

from __future__ import annotations

import math
from typing import Any

from sar_framework.sim.costmaps import Layer
from sar_framework.sim.lifecycle import Nav2LifecycleNode, optional_type
from sar_framework.sim.navigation import Navigator

_CLEARING = (
    ("ClearEntireCostmap", "clear_entirely", "clear entirely"),
    ("ClearCostmapAroundRobot", "clear_around", "clear around the robot in"),
    ("ClearCostmapExceptRegion", "clear_except", "clear except a region of"),
)


def costmap_node(layer: Layer, owner: Nav2LifecycleNode, navigator: Navigator
                 ) -> Nav2LifecycleNode:
    """Create ``/<costmap>/<costmap>`` with its clearing services, managed by ``owner``.

    Args:
        layer: Which costmap.
        owner: The server node whose lifecycle it follows.
        navigator: Knows the robot's pose and holds the costmaps.
    """
    name = layer.value
    node = Nav2LifecycleNode(name, namespace=name)
    owner.children.append(node)
    for type_name, prefix, verb in _CLEARING:
        kind = optional_type("nav2_msgs.srv", type_name, needed_by=f"{name}/{prefix}_{name}")
        if kind is None:
            continue

        def on_clear(request: Any, response: Any, prefix: str = prefix, verb: str = verb) -> Any:
            costmaps = navigator.costmaps
            pose = navigator.state().pose
            distance = float(getattr(request, "reset_distance", 0.0))
            if prefix == "clear_entirely":
                removed = costmaps.clear(layer)
            elif prefix == "clear_around":
                removed = costmaps.clear_around(layer, (pose.x, pose.y), distance)
            else:
                removed = costmaps.clear_except(layer, (pose.x, pose.y), distance)
            node.get_logger().info(f"Received request to {verb} the {name}: "
                                   f"{removed} phantom obstacles removed")
            return response

        node.create_service(kind, f"{prefix}_{name}", on_clear, callback_group=node.group)
    return node


def serve_is_path_valid(node: Nav2LifecycleNode, navigator: Navigator) -> None:
    """Serve ``is_path_valid`` on ``node`` (the planner server) if IsPathValid exists."""
    kind = optional_type("nav2_msgs.srv", "IsPathValid", needed_by="is_path_valid")
    if kind is None:
        return

    def on_request(request: Any, response: Any) -> Any:
        points = [(p.pose.position.x, p.pose.position.y) for p in request.path.poses]
        if not points:
            response.is_valid = False
            return response
        here = navigator.state().pose
        nearest = min(range(len(points)),
                      key=lambda i: math.hypot(points[i][0] - here.x, points[i][1] - here.y))
        planner = navigator.planner
        invalid = [i for i in range(nearest, len(points)) if planner.is_lethal(*points[i])]
        response.is_valid = not invalid
        if hasattr(response, "invalid_pose_indices"):
            response.invalid_pose_indices = invalid
        return response

    node.create_service(kind, "is_path_valid", on_request, callback_group=node.group)
