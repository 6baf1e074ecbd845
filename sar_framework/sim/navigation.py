"""Goal execution for the embedded Nav2 stand-in: plan once per goal, drive, finish.

Plain Python (no ROS), thread-safe. The physics loop calls :meth:`Navigator.step`; the
``navigate_to_pose`` server calls :meth:`Navigator.start` / :meth:`Navigator.cancel` from
executor threads and waits on :attr:`Goal.done`.

Outcomes follow Nav2's ``bt_navigator`` (Jazzy):

- a goal whose plan fails is accepted, then ABORTED with ``error_code`` UNKNOWN and the
  planner's reason in ``error_msg``;
- a new goal preempts the running one: the old goal ends ABORTED with an empty result
  (``nav2_util::SimpleActionServer::accept_pending_goal`` aborts it with an empty result);
- a cancelled goal stops the robot and ends CANCELED;
- success needs the robot within the xy and yaw tolerances (the drive model's arrival).
"""

from __future__ import annotations

import enum
import threading
from collections.abc import Callable
from dataclasses import dataclass, field

from sar_framework.sim.drive import DiffDrive
from sar_framework.sim.faults import Faults
from sar_framework.sim.planner import GridPlanner, PlanningError
from sar_framework.sim.world import Pose2D

ERROR_NONE = 0
"""``NavigateToPose.Result.NONE``."""
ERROR_UNKNOWN = 9000
"""``NavigateToPose.Result.UNKNOWN``."""


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
    """

    pose: Pose2D
    distance_remaining: float
    estimated_time_remaining: float
    navigation_time: float


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


class Navigator:
    """Runs goals on a :class:`DiffDrive` with paths from a :class:`GridPlanner`.

    Args:
        robot: The drive model (owned by the navigator from now on).
        planner: The planner (map already inflated).
        faults: Injected faults (``abort_goal_numbers``/``abort_delay_s`` are used here).
        listener: Told about every goal start and end (trace file, logs).
    """

    def __init__(
        self,
        robot: DiffDrive,
        planner: GridPlanner,
        faults: Faults | None = None,
        listener: GoalListener | None = None,
    ) -> None:
        self._robot = robot
        self._planner = planner
        self._faults = faults or Faults()
        self._listener = listener
        self._lock = threading.Lock()
        self._current: Goal | None = None
        self._accepted = 0
        self._planning = 0
        self._now_s = 0.0

    # ------------------------------------------------------------------ queries

    @property
    def accepted_count(self) -> int:
        """How many goals have been started."""
        return self._accepted

    @property
    def planning(self) -> bool:
        """True while a plan is being computed (the physics loop holds time meanwhile)."""
        return self._planning > 0

    @property
    def current(self) -> Goal | None:
        """The active goal, if any."""
        with self._lock:
            return self._current

    def state(self) -> RobotState:
        """Return a consistent snapshot of the robot."""
        with self._lock:
            linear, angular = self._robot.velocity
            return RobotState(self._robot.pose, linear, angular, self._robot.odometry)

    def progress(self, goal: Goal) -> Progress:
        """Return ``goal``'s progress now (zero distance once it has ended)."""
        with self._lock:
            pose = self._robot.pose
            if goal is self._current and goal.active:
                return Progress(
                    pose,
                    self._robot.distance_remaining(),
                    self._robot.estimated_time_remaining(),
                    self._now_s - goal.started_s,
                )
            end = goal.finished_s if goal.finished_s is not None else self._now_s
            return Progress(pose, 0.0, 0.0, end - goal.started_s)

    # ------------------------------------------------------------------ commands

    def start(self, target: Pose2D) -> Goal:
        """Start a goal, preempting the active one; plan from the robot's pose.

        Planning runs outside the lock; :attr:`planning` is True meanwhile so the physics
        loop can hold simulated time (a plan then takes no simulated time, whatever the
        speed factor or the machine's load).

        Args:
            target: The goal pose, map frame.

        Returns:
            The goal; already ABORTED (with the reason) if no plan could be made.
        """
        with self._lock:
            self._accepted += 1
            goal = Goal(number=self._accepted, target=target, started_s=self._now_s)
            if self._faults.aborts(goal.number):
                goal.abort_at_s = goal.started_s + self._faults.abort_delay_s
            start = self._robot.pose
            self._planning += 1
        try:
            path = self._planner.plan((start.x, start.y), (target.x, target.y))
            failure = ""
        except PlanningError as exc:
            path, failure = [], str(exc)
        except BaseException:
            with self._lock:
                self._planning -= 1
            raise
        with self._lock:
            self._planning -= 1
            # A later goal may have started while this one was planning: it wins.
            if self._current is not None and self._current.number > goal.number:
                self._notify(goal)
                self._finish(goal, Outcome.ABORTED, ERROR_NONE, "")
                return goal
            previous = self._current
            if previous is not None and previous.active:
                self._finish(previous, Outcome.ABORTED, ERROR_NONE, "")
            self._current = goal
            self._notify(goal)
            if failure:
                self._robot.cancel()
                self._finish(goal, Outcome.ABORTED, ERROR_UNKNOWN, failure)
            else:
                goal.path = path
                self._robot.follow(path, target.yaw)
        return goal

    def cancel(self, goal: Goal) -> bool:
        """Cancel ``goal`` if it is the active one: the robot stops, the goal is CANCELED.

        Returns:
            Whether the goal was active (and is now cancelled).
        """
        with self._lock:
            if goal is not self._current or not goal.active:
                return False
            self._robot.cancel()
            self._finish(goal, Outcome.CANCELED, ERROR_NONE, "")
            return True

    def abort_active(self, reason: str) -> Goal | None:
        """Abort the active goal (e.g. at shutdown) and stop the robot.

        Args:
            reason: The ``error_msg``.

        Returns:
            The aborted goal, or None if none was active.
        """
        with self._lock:
            goal = self._current
            if goal is None or not goal.active:
                return None
            self._robot.cancel()
            self._finish(goal, Outcome.ABORTED, ERROR_UNKNOWN, reason)
            return goal

    def step(self, dt: float, now_s: float) -> None:
        """Advance the robot by ``dt`` and settle the active goal.

        Args:
            dt: Simulated seconds.
            now_s: Simulated time at the end of the step.
        """
        with self._lock:
            self._robot.step(dt)
            self._now_s = now_s
            goal = self._current
            if goal is None or not goal.active:
                return
            arrived = self._robot.succeeded
            if goal.abort_at_s is not None and (now_s >= goal.abort_at_s or arrived):
                self._robot.cancel()
                self._finish(
                    goal,
                    Outcome.ABORTED,
                    ERROR_UNKNOWN,
                    f"injected fault: goal {goal.number} aborted (abort_goal_numbers)",
                )
            elif arrived and self._robot.within_tolerance():
                self._finish(goal, Outcome.SUCCEEDED, ERROR_NONE, "")
            elif not self._robot.active:
                self._finish(goal, Outcome.ABORTED, ERROR_UNKNOWN, "controller stopped")

    # ------------------------------------------------------------------ internals

    def _finish(self, goal: Goal, outcome: Outcome, code: int, message: str) -> None:
        """End ``goal`` (lock held)."""
        goal.outcome = outcome
        goal.error_code = code
        goal.error_msg = message
        goal.finished_s = self._now_s
        self._notify(goal)
        goal.done.set()

    def _notify(self, goal: Goal) -> None:
        """Tell the listener about ``goal`` (lock held)."""
        if self._listener is not None:
            linear, angular = self._robot.velocity
            state = RobotState(self._robot.pose, linear, angular, self._robot.odometry)
            self._listener(goal, self._now_s, state)

