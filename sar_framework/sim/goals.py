"""The goal model of the embedded Nav2 stand-in: kinds, outcomes, progress, Jazzy's codes.

Plain Python (no ROS). See :mod:`sar_framework.sim.navigation` for how goals run.
"""

from __future__ import annotations

import enum
import threading
from collections.abc import Callable
from dataclasses import dataclass, field

from sar_framework.sim.world import Pose2D

ERROR_NONE = 0
"""``NavigateToPose.Result.NONE`` (also the code of a goal ended by shutdown or preemption)."""
FOLLOW_PATH_UNKNOWN = 100
"""``FollowPath.Result.UNKNOWN``: the controller stopped short of the goal."""
FOLLOW_PATH_NO_PROGRESS = 105
"""``FollowPath.Result.FAILED_TO_MAKE_PROGRESS``: an injected abort, a stuck controller."""
FOLLOW_PATH_NO_VALID_CONTROL = 106
"""``FollowPath.Result.NO_VALID_CONTROL``: the path runs through a local costmap obstacle."""


class Kind(enum.Enum):
    """What a goal makes the robot do."""

    NAVIGATE = "navigate"
    """Plan through the via poses to the target, then follow the plan."""
    FOLLOW = "follow"
    """Follow a given path (the controller's ``follow_path``)."""
    SPIN = "spin"
    """Turn in place by an angle."""
    STRAIGHT = "straight"
    """Drive straight by a signed distance (``backup``)."""
    WAIT = "wait"
    """Stand still for a while."""


class Outcome(enum.Enum):
    """Where a goal stands."""

    ACTIVE = "active"
    SUCCEEDED = "succeeded"
    ABORTED = "aborted"
    CANCELED = "canceled"


@dataclass
class Progress:
    """A consistent snapshot of a goal's progress (for feedback).

    Attributes:
        pose: The robot's pose, map frame.
        distance_remaining: Metres left along the path.
        estimated_time_remaining: Seconds left at full speed.
        navigation_time: Simulated seconds since the goal started.
        motion_done: Radians turned (spin) or metres driven (straight) so far.
        poses_remaining: Via poses not yet passed, plus the target.
        time_left: Simulated seconds to the goal's deadline (0 without one).
        linear: Forward speed, m/s.
    """

    pose: Pose2D
    distance_remaining: float
    estimated_time_remaining: float
    navigation_time: float
    motion_done: float = 0.0
    poses_remaining: int = 1
    time_left: float = 0.0
    linear: float = 0.0


@dataclass
class Goal:
    """One accepted ``navigate_to_pose`` goal.

    Attributes:
        number: 1-based count of accepted goals.
        target: The goal pose, map frame.
        started_s: Simulated time it started.
        path: The planned waypoints (empty when planning failed).
        outcome: Current outcome.
        error_code: Result code (``ERROR_NONE`` unless a failure).
        error_msg: Human-readable reason of a failure ("" otherwise).
        finished_s: Simulated time it ended (None while active).
        abort_at_s: Simulated time an injected fault aborts it (None: no fault).
        kind: What the robot does.
        amount: A spin's angle or a straight motion's distance, signed.
        deadline_s: Simulated time the goal times out (WAIT: succeeds) at; None: never.
        timeout_code: ``error_code`` of a timeout.
        legs: The planned legs still to drive after the current one, each with the yaw
            to finish it at (through poses: one leg per pose).
        done: Set once the goal has ended.
    """

    number: int
    target: Pose2D
    started_s: float
    path: list[tuple[float, float]] = field(default_factory=list)
    outcome: Outcome = Outcome.ACTIVE
    error_code: int = ERROR_NONE
    error_msg: str = ""
    finished_s: float | None = None
    abort_at_s: float | None = None
    kind: Kind = Kind.NAVIGATE
    amount: float = 0.0
    deadline_s: float | None = None
    timeout_code: int = ERROR_NONE
    legs: list[tuple[list[tuple[float, float]], float]] = field(default_factory=list)
    done: threading.Event = field(default_factory=threading.Event, repr=False)

    @property
    def active(self) -> bool:
        """True until the goal has ended."""
        return self.outcome is Outcome.ACTIVE


@dataclass
class RobotState:
    """The robot as the physics loop publishes it.

    Attributes:
        pose: Map-frame pose.
        linear: Forward speed, m/s.
        angular: Turn rate, rad/s.
        odometry: Distance driven so far, metres.
    """

    pose: Pose2D
    linear: float
    angular: float
    odometry: float


GoalListener = Callable[[Goal, float, RobotState], None]
"""Called as ``listener(goal, sim_s, robot)`` when a goal starts and when it ends.

It runs with the navigator's lock held: it must not call back into the navigator.
"""
