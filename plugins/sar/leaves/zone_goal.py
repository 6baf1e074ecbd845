"""SetZoneGoal and MarkZoneReached: a zone visit driven by a navigator tree of Nav2's shape.

NavigateToZone sends one ``navigate_to_pose`` goal and lets Nav2's navigator run its own
tree. A mission that holds the navigator tree itself (``trees/examples/
search_and_rescue_nav2.yaml``: ComputePathToPose, FollowPath and their recoveries as a
subtree) needs the current zone's pose on the blackboard instead, and someone to say the
zone was reached: SetZoneGoal writes the pose to its ``goal`` port (and announces the
zone as NavigateToZone does), MarkZoneReached tells the ZoneManager once the subtree
succeeded (the mission's ``Reached zone_a.`` line, mission.json's ``zones_visited``).

Neither talks to a server; both work without ROS except for the message type of the
pose (``geometry_msgs``, imported when the goal is first written).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from py_trees.common import Status

from sar_framework.engine.plugin import Param, leaf
from sar_framework.engine.ports import OutputPort
from sar_framework.events.event import EventKind

from ._logging_leaf import LoggingLeaf

if TYPE_CHECKING:
    from sar_plugins.sar.zone_manager import ZoneManager


def pose_stamped(x: float, y: float, yaw: float, frame_id: str, stamp: Any = None) -> Any:
    """A ``geometry_msgs/PoseStamped`` at ``(x, y)`` facing ``yaw`` radians in ``frame_id``."""
    from geometry_msgs.msg import PoseStamped

    msg = PoseStamped()
    msg.header.frame_id = frame_id
    if stamp is not None:
        msg.header.stamp = stamp
    msg.pose.position.x, msg.pose.position.y = float(x), float(y)
    msg.pose.orientation.z, msg.pose.orientation.w = math.sin(yaw / 2.0), math.cos(yaw / 2.0)
    return msg


@leaf(
    params=[Param("frame_id", str, default="map", description="Frame of the goal pose.")],
    ports=[OutputPort("goal", "geometry_msgs/msg/PoseStamped",
                      description="The current zone's pose (x, y, yaw).")],
    context=["zone_manager"],
)
class SetZoneGoal(LoggingLeaf):
    """Write the current zone's pose to ``goal`` and announce the zone; SUCCESS.

    Logs ``--- Zone 1/4: zone_a (-3.00, 3.00) ---`` and tells the mission a navigation
    goal was set, as NavigateToZone does when it sends its goal. FAILURE when no zone is
    left (``goal`` is then not written).

    Args:
        name: The behaviour's name.
        ports: The ``goal`` output.
        zone_manager: The mission's shared zone state.
        frame_id: Frame of the goal pose.
    """

    def __init__(self, name: str, *, ports: Any, zone_manager: ZoneManager,
                 frame_id: str) -> None:
        super().__init__(name)
        self.ports = ports
        self.zone_manager = zone_manager
        self.frame_id = frame_id

    def update(self) -> Status:
        """Write the goal, announce it and return SUCCESS (FAILURE without a zone)."""
        try:
            zone = self.zone_manager.current_zone()
        except IndexError:
            self.feedback_message = "no zone left to set as the goal"
            return Status.FAILURE
        index, total = self.zone_manager.current_index() + 1, self.zone_manager.total_zones()
        stamp = self._node.get_clock().now().to_msg() if self._node is not None else None
        self.ports.set("goal", pose_stamped(zone["x"], zone["y"], zone["yaw"], self.frame_id,
                                            stamp))
        announce = f"--- Zone {index}/{total}: {zone['id']} ({zone['x']:.2f}, {zone['y']:.2f}) ---"
        self.feedback_message = f"goal: {zone['id']}"
        self._events.emit(EventKind.NAVIGATION, source=self, zone_id=zone["id"],
                          message=announce, position=(zone["x"], zone["y"]))
        logger = self._node.get_logger() if self._node is not None else self.logger
        logger.info(announce)
        return Status.SUCCESS


@leaf(context=["zone_manager"])
class MarkZoneReached(LoggingLeaf):
    """Tell the ZoneManager its current zone was reached; SUCCESS.

    Put it after the navigation that drove there: the mission then says ``Reached
    zone_a.`` and counts the zone visited. FAILURE when no zone is left.

    Args:
        name: The behaviour's name.
        zone_manager: The mission's shared zone state.
    """

    def __init__(self, name: str, *, zone_manager: ZoneManager) -> None:
        super().__init__(name)
        self.zone_manager = zone_manager

    def update(self) -> Status:
        """Mark the current zone reached and return SUCCESS (FAILURE without a zone)."""
        if not self.zone_manager.has_remaining():
            self.feedback_message = "no zone to mark reached: every zone has been visited"
            return Status.FAILURE
        zone_id = self.zone_manager.current_zone()["id"]
        self.zone_manager.mark_reached(zone_id)  # the zone manager tells the events
        self.feedback_message = f"Reached {zone_id}."
        (self._node.get_logger() if self._node is not None else self.logger).info(
            self.feedback_message)
        return Status.SUCCESS
