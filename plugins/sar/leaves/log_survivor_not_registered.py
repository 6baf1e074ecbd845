"""LogSurvivorNotRegistered: the survivor is not this robot's to report; say why, go on."""

from __future__ import annotations

from typing import TYPE_CHECKING

from py_trees.common import Status

from sar_framework.engine.plugin import Param, leaf

from ._logging_leaf import LoggingLeaf

if TYPE_CHECKING:
    from .register_survivor import RegisterSurvivor


@leaf(params=[Param("registrar", ref="RegisterSurvivor",
                    description="id of the RegisterSurvivor leaf whose answer to check.")])
class LogSurvivorNotRegistered(LoggingLeaf):
    """SUCCESS when the fleet did not give this robot the current survivor to report.

    Two cases, both SUCCESS so the patrol goes on (and a duplicate never reaches
    LogNoDetection's "No survivor found"):

    * another robot already has it: RegisterSurvivor has noted and logged that; this leaf
      only repeats it as its feedback message;
    * the registration failed (the registry refused it or did not answer): logged as a
      warning, ``Survivor at (x, y) not registered: <reason>``, like LogReportFailure.

    FAILURE when the referenced RegisterSurvivor did not fail on the current detection (no
    survivor, or this robot reports it), so a selector goes on to its next child.

    Args:
        name: The behaviour's name.
        registrar: The RegisterSurvivor leaf.
    """

    def __init__(self, name: str, *, registrar: RegisterSurvivor) -> None:
        super().__init__(name)
        self.registrar = registrar

    def update(self) -> Status:
        """Return SUCCESS on a duplicate or a failed registration (logged); else FAILURE."""
        duplicate = self.registrar.duplicate()
        if duplicate is not None:
            self.feedback_message = duplicate
            return Status.SUCCESS
        failure = self.registrar.failed_registration()
        if failure is None:
            self.feedback_message = "the survivor was registered to this robot, or none found"
            return Status.FAILURE
        self.say(failure, warning=True)
        return Status.SUCCESS
