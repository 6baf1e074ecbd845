"""BT.CPP 4's status-converting decorators.

Inverter, ForceSuccess, ForceFailure and KeepRunningUntilFailure.

Each ticks its child once per tick and turns the child's result into its own; RUNNING
and SKIPPED pass through (KeepRunningUntilFailure turns SKIPPED into RUNNING, as BT.CPP
does).
"""

from __future__ import annotations

from sar_framework.engine.nodes.controls.base import BtDecorator, Outcome, Steps


class _Converter(BtDecorator):
    """Tick the child once; its result, converted by ``converts``, is the decorator's."""

    #: The child's results that change, and what they become; the others pass through.
    converts: dict[Outcome, Outcome]

    def decorate(self) -> Steps:
        """Convert the child's result (a completed child is reset)."""
        result = yield from self.tick_child()
        if result.completed:
            self.reset_child()
        return self.converts.get(result, result)


class Inverter(_Converter):
    """BT.CPP ``Inverter``: SUCCESS becomes FAILURE and FAILURE becomes SUCCESS."""

    converts = {Outcome.SUCCESS: Outcome.FAILURE, Outcome.FAILURE: Outcome.SUCCESS}


class ForceSuccess(_Converter):
    """BT.CPP ``ForceSuccess``: a completed child gives SUCCESS."""

    converts = {Outcome.FAILURE: Outcome.SUCCESS}


class ForceFailure(_Converter):
    """BT.CPP ``ForceFailure``: a completed child gives FAILURE."""

    converts = {Outcome.SUCCESS: Outcome.FAILURE}


class KeepRunningUntilFailure(_Converter):
    """BT.CPP ``KeepRunningUntilFailure``: RUNNING until the child fails."""

    converts = {Outcome.SUCCESS: Outcome.RUNNING, Outcome.SKIPPED: Outcome.RUNNING}
