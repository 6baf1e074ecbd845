"""LogReportFailure: say that the base refused (or never answered) a survivor's report."""

from __future__ import annotations

from typing import TYPE_CHECKING

from py_trees.common import Status

from sar_framework.engine.plugin import Param, leaf

from ._logging_leaf import LoggingLeaf

if TYPE_CHECKING:
    from .notify_base import NotifyBase


@leaf(params=[Param("notifier", ref="NotifyBase",
                    description="id of the NotifyBase leaf whose report to check.")])
class LogReportFailure(LoggingLeaf):
    """Log why the base did not acknowledge the current survivor; SUCCESS, so the patrol goes on.

    Logs (as a warning) ``Report for survivor_N refused by base: not acknowledged``, or
    ``Report for survivor_N failed: <reason>`` when the service did not answer. FAILURE
    when the referenced NotifyBase did not fail on the current detection (no survivor, or
    the report was acknowledged), so a selector goes on to its next child.

    Args:
        name: The behaviour's name.
        notifier: The NotifyBase leaf.
    """

    def __init__(self, name: str, *, notifier: NotifyBase) -> None:
        super().__init__(name)
        self.notifier = notifier

    def update(self) -> Status:
        """Log the failed report and return SUCCESS; FAILURE when no report failed."""
        failure = self.notifier.failed_report()
        if failure is None:
            self.feedback_message = "no failed report"
            return Status.FAILURE
        self.say(failure, warning=True)
        return Status.SUCCESS
