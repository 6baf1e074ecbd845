"""SecondLook: a bound judged on two ticks, so one slow tick alone fails nothing.

A tick that comes late may find a bound passed while the answer already waits in the
executor's queue: the executor has not had its turn since. The first tick that sees the bound
passed gives the executor that turn; only a tick after it, with the bound still passed and
still no answer, fails the call.
"""

from __future__ import annotations


class SecondLook:
    """Whether a passed bound has been seen passed at an earlier tick too."""

    def __init__(self) -> None:
        self._seen = False

    def reset(self) -> None:
        """Forget the earlier sighting (a new request or goal begins)."""
        self._seen = False

    def fails(self, passed: bool) -> bool:
        """Whether the bound fails now.

        Args:
            passed: Whether the bound has passed at this tick.

        Returns:
            True only when it passed at this tick and had already passed at an earlier one.
        """
        if not passed:
            return False
        if self._seen:
            return True
        self._seen = True  # first seen late: give the executor its turn
        return False
