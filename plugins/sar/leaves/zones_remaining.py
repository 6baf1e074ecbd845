"""ZonesRemaining: condition, true while the mission has a zone left to visit."""

from __future__ import annotations

from py_trees.common import Status

from sar_framework.engine.plugin import leaf

from ._zone_leaf import ZoneLeaf


@leaf(context=["zone_manager"], condition=True)
class ZonesRemaining(ZoneLeaf):
    """Condition: SUCCESS while the ZoneManager has a zone left to visit, else FAILURE.

    Never RUNNING and needs no ROS.
    """

    def update(self) -> Status:
        """Return SUCCESS if a zone remains, FAILURE otherwise."""
        index, total = self.progress()
        if self.zone_manager.has_remaining():
            self.feedback_message = f"zone {index + 1}/{total} next"
            return Status.SUCCESS
        self.feedback_message = f"all {total} zones visited"
        return Status.FAILURE
