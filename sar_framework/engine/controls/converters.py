"""BT.CPP 4's status-converting decorators.

Inverter, ForceSuccess, ForceFailure and KeepRunningUntilFailure.

Each ticks its child once per tick and turns the child's result into its own; RUNNING
and SKIPPED pass through (KeepRunningUntilFailure turns SKIPPED into RUNNING, as BT.CPP
does).
"""

from __future__ import annotations

from sar_framework.engine.controls.base import BtDecorator, Outcome, Steps


class Inverter(BtDecorator):
    """BT.CPP ``Inverter``: SUCCESS becomes FAILURE and FAILURE becomes SUCCESS.

    Args:
        name: The behaviour's name.
        child: The decorated behaviour.
    """

    def decorate(self) -> Steps:
        """Swap the child's SUCCESS and FAILURE."""
        result = yield from self.tick_child()
        if result is Outcome.SUCCESS:
            self.reset_child()
            return Outcome.FAILURE
        if result is Outcome.FAILURE:
            self.reset_child()
            return Outcome.SUCCESS
        return result


class _Force(BtDecorator):
    """A completed child gives ``forced``."""

    forced: Outcome

    def decorate(self) -> Steps:
        """Replace a completed child's result."""
        result = yield from self.tick_child()
        if result.completed:
            self.reset_child()
            return self.forced
        return result


class ForceSuccess(_Force):
    """BT.CPP ``ForceSuccess``: a completed child gives SUCCESS.

    Args:
        name: The behaviour's name.
        child: The decorated behaviour.
    """

    forced = Outcome.SUCCESS


class ForceFailure(_Force):
    """BT.CPP ``ForceFailure``: a completed child gives FAILURE.

    Args:
        name: The behaviour's name.
        child: The decorated behaviour.
    """

    forced = Outcome.FAILURE


class KeepRunningUntilFailure(BtDecorator):
    """BT.CPP ``KeepRunningUntilFailure``: RUNNING until the child fails.

    Args:
        name: The behaviour's name.
        child: The decorated behaviour.
    """

    def decorate(self) -> Steps:
        """FAILURE when the child fails, RUNNING otherwise."""
        result = yield from self.tick_child()
        if result.completed:
            self.reset_child()
        return Outcome.FAILURE if result is Outcome.FAILURE else Outcome.RUNNING
