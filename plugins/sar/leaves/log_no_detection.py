"""LogNoDetection: say that the current zone held no survivor."""

from __future__ import annotations

from typing import TYPE_CHECKING

from py_trees.common import Status

from sar_framework.engine.plugin import leaf

from ._logging_leaf import LoggingLeaf

if TYPE_CHECKING:
    from sar_plugins.sar.zone_manager import ZoneManager


@leaf(context=["zone_manager"])
class LogNoDetection(LoggingLeaf):
    """Log ``No survivor found at <zone>.`` for the current zone; SUCCESS.

    The line goes to the ROS node's logger when ``setup(node=...)`` gave one, otherwise to
    the py_trees logger. FAILURE only when every zone has already been visited (there is no
    current zone to speak of).

    Args:
        name: The behaviour's name.
        zone_manager: The mission's shared zone state.
    """

    def __init__(self, name: str, *, zone_manager: ZoneManager) -> None:
        super().__init__(name)
        self.zone_manager = zone_manager

    def update(self) -> Status:
        """Log the line and return SUCCESS."""
        try:
            zone_id = self.zone_manager.current_zone()["id"]
        except IndexError:
            self.feedback_message = "no current zone: every zone has been visited"
            return Status.FAILURE
        self.say(f"No survivor found at {zone_id}.")
        return Status.SUCCESS
