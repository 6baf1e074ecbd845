"""ZoneLeaf: the base of the ROS-free leaves that read or move the mission's zones.

Not a plugin itself (it carries no ``@leaf`` mark).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import py_trees

if TYPE_CHECKING:
    from sar_plugins.sar.zone_manager import ZoneManager


class ZoneLeaf(py_trees.behaviour.Behaviour):
    """A leaf over the mission's shared zone state.

    Args:
        name: The behaviour's name.
        zone_manager: The mission's shared zone state.
    """

    def __init__(self, name: str, *, zone_manager: ZoneManager) -> None:
        super().__init__(name=name)
        self.zone_manager = zone_manager

    def progress(self) -> tuple[int, int]:
        """The current zone's index (the number of zones once all are visited) and the total."""
        return self.zone_manager.current_index(), self.zone_manager.total_zones()
