"""AdvanceZone: move the mission on to its next zone."""

from __future__ import annotations

from typing import TYPE_CHECKING

import py_trees
from py_trees.common import Status

from sar_framework.engine.plugin import leaf

if TYPE_CHECKING:
    from sar_framework.mission.zone_manager import ZoneManager


@leaf(context=["zone_manager"])
class AdvanceZone(py_trees.behaviour.Behaviour):
    """Advance the ZoneManager to the next zone; always SUCCESS.

    Advancing past the last zone is a no-op, so the leaf is safe to tick at any time.

    Args:
        name: The behaviour's name.
        zone_manager: The mission's shared zone state.
    """

    def __init__(self, name: str, *, zone_manager: ZoneManager) -> None:
        super().__init__(name=name)
        self.zone_manager = zone_manager

    def update(self) -> Status:
        """Advance and return SUCCESS."""
        self.zone_manager.advance()
        index, total = self.zone_manager.current_index(), self.zone_manager.total_zones()
        self.feedback_message = (f"next zone {index + 1}/{total}" if index < total
                                 else f"all {total} zones visited")
        return Status.SUCCESS
