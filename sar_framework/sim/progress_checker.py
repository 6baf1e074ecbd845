"""The stuck-controller fault, seen through Nav2's progress checker (plain Python).

While :attr:`ProgressChecker.stuck_left` > 0 the controller makes no progress on a path
(``navigate_*`` and ``follow_path`` goals): the robot stands still, and after
``allowance_s`` simulated seconds the goal fails with FollowPath's FAILED_TO_MAKE_PROGRESS,
as Nav2's ``SimpleProgressChecker`` (``movement_time_allowance``) makes the controller
server fail. Each completed spin or straight motion (spin, backup, drive_on_heading: the
robot wriggles free) counts one down. The navigator's lock guards it.
"""

from __future__ import annotations

from dataclasses import dataclass

from sar_framework.sim.goals import FOLLOW_PATH_NO_PROGRESS, Goal, Kind


@dataclass
class ProgressChecker:
    """The stuck controller's state.

    Attributes:
        stuck_left: Recovery motions still needed (0: the controller moves).
        allowance_s: Simulated seconds without progress before a goal fails.
    """

    stuck_left: int = 0
    allowance_s: float = 10.0

    def holds(self, goal: Goal | None) -> bool:
        """Whether ``goal`` is a path goal the stuck controller does not move."""
        return (self.stuck_left > 0 and goal is not None and goal.active
                and goal.kind in (Kind.NAVIGATE, Kind.FOLLOW))

    def failure(self, goal: Goal, now_s: float) -> tuple[int, str] | None:
        """The failure of a held ``goal`` once the allowance has passed, else None."""
        if now_s - goal.started_s < self.allowance_s:
            return None
        return (FOLLOW_PATH_NO_PROGRESS, "Failed to make progress: no movement in "
                f"{self.allowance_s:g} s (stuck_recoveries: {self.stuck_left} left)")

    def succeeded(self, goal: Goal) -> None:
        """Count a completed spin or straight motion down."""
        if goal.kind in (Kind.SPIN, Kind.STRAIGHT) and self.stuck_left > 0:
            self.stuck_left -= 1
