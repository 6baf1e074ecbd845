"""AdvanceZone: move the mission on to its next zone."""

from __future__ import annotations

from py_trees.common import Status

from sar_framework.engine.plugin import leaf

from ._zone_leaf import ZoneLeaf


@leaf(context=["zone_manager"])
class AdvanceZone(ZoneLeaf):
    """Advance the ZoneManager to the next zone; always SUCCESS.

    Advancing past the last zone is a no-op, so the leaf is safe to tick at any time.
    """

    def update(self) -> Status:
        """Advance and return SUCCESS."""
        self.zone_manager.advance()
        index, total = self.progress()
        self.feedback_message = (f"next zone {index + 1}/{total}" if index < total
                                 else f"all {total} zones visited")
        return Status.SUCCESS
