"""ZonesRemaining: condition, true while the mission has a zone left to visit."""

from __future__ import annotations

from typing import TYPE_CHECKING

import py_trees
from py_trees.common import Status

from sar_framework.engine.plugin import leaf

if TYPE_CHECKING:
    from sar_framework.mission.zone_manager import ZoneManager


@leaf(context=["zone_manager"], condition=True)
class ZonesRemaining(py_trees.behaviour.Behaviour):
    """Condition: SUCCESS while the ZoneManager has a zone left to visit, else FAILURE.

    Never RUNNING and needs no ROS.

    Args:
        name: The behaviour's name.
        zone_manager: The mission's shared zone state.
    """

    def __init__(self, name: str, *, zone_manager: ZoneManager) -> None:
        super().__init__(name=name)
        self.zone_manager = zone_manager

    def update(self) -> Status:
        """Return SUCCESS if a zone remains, FAILURE otherwise."""
        index, total = self.zone_manager.current_index(), self.zone_manager.total_zones()
        if self.zone_manager.has_remaining():
            self.feedback_message = f"zone {index + 1}/{total} next"
            return Status.SUCCESS
        self.feedback_message = f"all {total} zones visited"
        return Status.FAILURE
