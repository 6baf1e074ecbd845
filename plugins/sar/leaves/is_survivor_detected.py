"""IsSurvivorDetected: condition on the result of a DetectSurvivor leaf."""

from __future__ import annotations

from typing import TYPE_CHECKING

import py_trees
from py_trees.common import Status

from sar_framework.engine.plugin import Param, leaf

if TYPE_CHECKING:
    from .detect_survivor import DetectSurvivor


@leaf(condition=True, params=[Param("detector", ref="DetectSurvivor",
                    description="id of the DetectSurvivor leaf whose result to read.")])
class IsSurvivorDetected(py_trees.behaviour.Behaviour):
    """Condition: SUCCESS if the referenced DetectSurvivor leaf found a survivor, else FAILURE.

    Never RUNNING and needs no ROS; it reads the detector's :meth:`was_found`.

    Args:
        name: The behaviour's name.
        detector: The DetectSurvivor leaf.
    """

    def __init__(self, name: str, *, detector: DetectSurvivor) -> None:
        super().__init__(name=name)
        self.detector = detector

    def update(self) -> Status:
        """Return SUCCESS if the detector found a survivor, FAILURE otherwise."""
        pose = self.detector.survivor_pose()
        if self.detector.was_found() and pose is not None:
            self.feedback_message = f"survivor at ({pose[0]:.2f}, {pose[1]:.2f})"
            return Status.SUCCESS
        self.feedback_message = "no survivor detected"
        return Status.FAILURE
