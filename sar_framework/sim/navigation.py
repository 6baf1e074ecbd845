"""Goal execution for the embedded Nav2 stand-in: plan a goal, drive, finish.

Plain Python (no ROS), thread-safe. The physics loop calls :meth:`Navigator.step`; the
``navigate_to_pose`` server calls :meth:`Navigator.start` / :meth:`Navigator.cancel` from
executor threads and waits on :attr:`Goal.done`.

Outcomes follow Nav2's ``bt_navigator`` (Jazzy):

- a goal whose plan fails is accepted, then ABORTED with the planner's reason in
  ``error_msg`` and, as ``error_code``, the planner's ``ComputePathToPose`` code (Jazzy's
  bt_navigator reports the failing server's code, see ``error_code_names``; its own
  NavigateToPose result defines only NONE);
- a new goal preempts the running one: the old goal ends ABORTED with an empty result
  (``nav2_util::SimpleActionServer::accept_pending_goal`` aborts it with an empty result);
- a cancelled goal stops the robot and ends CANCELED;
- success needs the robot within the xy and yaw tolerances (the drive model's arrival);
- plans use the global costmap's phantoms; a path through a local one fails at once with
  NO_VALID_CONTROL (:mod:`.costmaps`); a stuck controller fails as :mod:`.progress_checker`;
- a fleet's other robots: a goal one covers ends at NavFn's approach point, and a robot
  another one holds replans at the global costmap's rate (:mod:`.detour`).
"""

from __future__ import annotations

import itertools
import math
import threading
from collections.abc import Callable, Sequence

from sar_framework.sim.costmaps import Costmaps
from sar_framework.sim.detour import Detour, plan_legs
from sar_framework.sim.drive import DiffDrive
from sar_framework.sim.faults import Faults
from sar_framework.sim.goals import (
    ERROR_NONE,
    FOLLOW_PATH_NO_PROGRESS,
    FOLLOW_PATH_UNKNOWN,
    Goal,
    GoalListener,
    Kind,
    Outcome,
    Progress,
    RobotState,
)
from sar_framework.sim.planner import GridPlanner, PlanningError
from sar_framework.sim.progress_checker import ProgressChecker
from sar_framework.sim.traffic import Traffic
from sar_framework.sim.world import Pose2D


def _length(points: Sequence[tuple[float, float]]) -> float:
    return sum(math.dist(a, b) for a, b in itertools.pairwise(points))


class Navigator:
    """Runs goals on a :class:`DiffDrive` with paths from a :class:`GridPlanner`.

    Args:
        robot: The drive model (owned by the navigator from now on).
        planner: The planner (map already inflated).
        faults: Injected faults (``abort_goal_numbers``/``abort_delay_s`` are used here).
        listener: Told about every goal start and end (trace file, logs).
        costmaps: The costmaps' phantoms over ``planner``'s grid (default: none).
        traffic: The other robots of a fleet (default: none), see :mod:`.traffic`.
    """

    def __init__(
        self,
        robot: DiffDrive,
        planner: GridPlanner,
        faults: Faults | None = None,
        listener: GoalListener | None = None,
        costmaps: Costmaps | None = None,
        *,
        traffic: Traffic | None = None,
    ) -> None:
        self._robot = robot
        self._costmaps = costmaps or Costmaps.over(planner)
        self._detour = Detour(traffic, self._costmaps) if traffic is not None else None
        self._faults = faults or Faults()
        self._checker = ProgressChecker(self._faults.stuck_recoveries,
                                        self._faults.movement_time_allowance)
        self.generation = 0
        """Counts resets: a multi-goal action stops when it changes (see :meth:`reset`)."""
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
    def planner(self) -> GridPlanner:
        """The planner now (over the global costmap's phantoms when there are costmaps)."""
        return self._costmaps.planner()

    @property
    def costmaps(self) -> Costmaps:
        """The costmaps' phantoms."""
        return self._costmaps

    def is_free(self, x: float, y: float) -> bool:
        """Whether a path may pass through ``(x, y)`` (see :meth:`GridPlanner.is_free`)."""
        return self.planner.is_free(x, y)

    @property
    def stuck_left(self) -> int:
        """Recovery motions the stuck controller still needs (0: it moves)."""
        return self._checker.stuck_left

    def set_stuck(self, recoveries: int, allowance_s: float) -> None:
        """(Re-)arm the stuck controller (see :class:`ProgressChecker`)."""
        with self._lock:
            self._checker = ProgressChecker(max(int(recoveries), 0), float(allowance_s))

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
            robot = self._robot
            pose = robot.pose
            elapsed_end = goal.finished_s if goal.finished_s is not None else self._now_s
            time_left = max(goal.deadline_s - self._now_s, 0.0) if goal.deadline_s else 0.0
            if goal is self._current and goal.active:
                later = sum(_length(leg) for leg, _ in goal.legs)
                remaining = robot.distance_remaining() + later
                return Progress(
                    pose, remaining,
                    robot.estimated_time_remaining() + later / robot.limits.max_linear,
                    self._now_s - goal.started_s,
                    motion_done=abs(goal.amount) - robot.motion_left,
                    poses_remaining=1 + len(goal.legs),
                    time_left=time_left,
                    linear=robot.velocity[0],
                )
            return Progress(pose, 0.0, 0.0, elapsed_end - goal.started_s,
                            motion_done=abs(goal.amount), poses_remaining=0)

    # ------------------------------------------------------------------ commands

    def start(self, target: Pose2D, via: Sequence[Pose2D] = ()) -> Goal:
        """Start a goal, preempting the active one; plan from the robot's pose.

        Planning runs outside the lock; :attr:`planning` is True meanwhile so the physics
        loop can hold simulated time (a plan then takes no simulated time, whatever the
        speed factor or the machine's load).

        Args:
            target: The goal pose, map frame.
            via: Poses to pass through first, in order (``navigate_through_poses``).

        Returns:
            The goal; already ABORTED (with the reason) if no plan could be made.
        """
        goal, start = self._new_goal(target, Kind.NAVIGATE)
        with self._lock:
            self._planning += 1
        try:
            legs = self.plan_through(start, [*via, target])
            failure, failure_code = "", ERROR_NONE
        except PlanningError as exc:
            legs, failure, failure_code = [], str(exc), exc.error_code
        finally:
            with self._lock:
                self._planning -= 1
        goal.path = [p for i, leg in enumerate(legs) for p in (leg if i == 0 else leg[1:])]
        if failure:
            return self._begin(goal, None, (failure_code, failure))
        yaws = [pose.yaw for pose in via] + [target.yaw]
        goal.legs = list(zip(legs[1:], yaws[1:], strict=True))
        return self._begin(goal, lambda: self._robot.follow(legs[0], yaws[0]),
                           self._costmaps.local_failure(goal.path))

    def plan_through(self, start: Pose2D, poses: Sequence[Pose2D]
                     ) -> list[list[tuple[float, float]]]:
        """:func:`~.detour.plan_legs` over the global costmap now (thread-safe)."""
        return plan_legs(self.planner, self._costmaps.robots, start, poses)

    def start_path(self, path: Sequence[tuple[float, float]], target: Pose2D) -> Goal:
        """Follow ``path`` (no planning) and finish facing ``target.yaw``."""
        goal, _ = self._new_goal(target, Kind.FOLLOW)
        goal.path = [(float(x), float(y)) for x, y in path]
        return self._begin(goal, lambda: self._robot.follow(path, target.yaw),
                           self._costmaps.local_failure(goal.path))

    def start_spin(self, angle: float, time_allowance_s: float, timeout_code: int) -> Goal:
        """Turn in place by ``angle`` radians; time out after ``time_allowance_s``."""
        pose = self.state().pose
        goal, _ = self._new_goal(Pose2D(pose.x, pose.y, pose.yaw + angle), Kind.SPIN)
        goal.amount = angle
        self._set_deadline(goal, time_allowance_s, timeout_code)
        return self._begin(goal, lambda: self._robot.spin(angle))

    def start_straight(self, distance: float, speed: float, time_allowance_s: float,
                       timeout_code: int) -> Goal:
        """Drive ``distance`` metres straight (negative: back); time out as given."""
        pose = self.state().pose
        end = Pose2D(pose.x + distance * math.cos(pose.yaw),
                     pose.y + distance * math.sin(pose.yaw), pose.yaw)
        goal, _ = self._new_goal(end, Kind.STRAIGHT)
        goal.amount = distance
        self._set_deadline(goal, time_allowance_s, timeout_code)
        return self._begin(goal, lambda: self._robot.drive_straight(distance, speed))

    def start_wait(self, seconds: float) -> Goal:
        """Stand still for ``seconds`` of simulated time, then succeed."""
        goal, _ = self._new_goal(self.state().pose, Kind.WAIT)
        self._set_deadline(goal, seconds, ERROR_NONE)
        return self._begin(goal, self._robot.cancel)

    def path_is_clear(self, a: Pose2D, b: Pose2D) -> bool:
        """Whether the robot can go straight from ``a`` to ``b``.

        Its centre must cross no lethal cell of the global costmap and its footprint no
        phantom of the local one.
        """
        planner = self.planner
        if not planner.segment_is_clear((a.x, a.y), (b.x, b.y), mask=planner.lethal):
            return False
        return self._costmaps.local_blocks([(a.x, a.y), (b.x, b.y)]) is None

    def reset(self, pose: Pose2D, reason: str) -> Goal | None:
        """Abort the active goal, put the robot at rest at ``pose``, restart goal numbers.

        Returns:
            The aborted goal, or None if none was active.
        """
        with self._lock:
            goal = self._current
            aborted = goal if goal is not None and goal.active else None
            self._robot.cancel()
            if aborted is not None:
                self._finish(aborted, Outcome.ABORTED, ERROR_NONE, reason)
            self._robot.set_pose(pose)
            self._current = None
            self._accepted = 0
            self.generation += 1
            return aborted

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
            self._finish(goal, Outcome.ABORTED, ERROR_NONE, reason)
            return goal

    def step(self, dt: float, now_s: float) -> None:
        """Advance the robot by ``dt`` and settle the active goal.

        Args:
            dt: Simulated seconds.
            now_s: Simulated time at the end of the step.
        """
        with self._lock:
            goal = self._current
            stuck = self._checker.holds(goal)
            held, failure = (False, None) if self._detour is None or stuck else \
                self._detour.hold(goal, self._robot, now_s, self._checker.allowance_s)
            if stuck:
                self._robot.stand_still()
            else:
                self._robot.step(dt, turn_only=held)
            self._now_s = now_s
            if goal is None or not goal.active:
                return
            if stuck:
                failure = self._checker.failure(goal, now_s)
            if failure is not None:
                self._robot.cancel()
                self._finish(goal, Outcome.ABORTED, *failure)
                return
            arrived = self._robot.succeeded
            if goal.abort_at_s is not None and (now_s >= goal.abort_at_s or arrived):
                self._robot.cancel()
                self._finish(
                    goal,
                    Outcome.ABORTED,
                    FOLLOW_PATH_NO_PROGRESS,
                    f"injected fault: goal {goal.number} aborted (abort_goal_numbers)",
                )
            elif goal.deadline_s is not None and now_s >= goal.deadline_s:
                self._robot.cancel()
                if goal.kind is Kind.WAIT:
                    self._finish(goal, Outcome.SUCCEEDED, ERROR_NONE, "")
                else:
                    self._finish(goal, Outcome.ABORTED, goal.timeout_code,
                                 f"{goal.kind.value} timed out")
            elif goal.kind is Kind.WAIT:
                return
            elif arrived and goal.legs:  # a via pose reached: drive the next leg
                leg, yaw = goal.legs.pop(0)
                self._robot.follow(leg, yaw)
            elif arrived and (goal.kind in (Kind.SPIN, Kind.STRAIGHT)
                              or self._robot.within_tolerance()):
                self._checker.succeeded(goal)
                self._finish(goal, Outcome.SUCCEEDED, ERROR_NONE, "")
            elif not self._robot.active:
                self._finish(goal, Outcome.ABORTED, FOLLOW_PATH_UNKNOWN, "controller stopped")

    # ------------------------------------------------------------------ internals

    def _new_goal(self, target: Pose2D, kind: Kind) -> tuple[Goal, Pose2D]:
        """Number a new goal (not yet current); return it and the robot's pose."""
        with self._lock:
            self._accepted += 1
            goal = Goal(number=self._accepted, target=target, started_s=self._now_s, kind=kind)
            if self._faults.aborts(goal.number):
                goal.abort_at_s = goal.started_s + self._faults.abort_delay_s
            return goal, self._robot.pose

    def _set_deadline(self, goal: Goal, seconds: float, code: int) -> None:
        if seconds > 0.0:
            goal.deadline_s = goal.started_s + seconds
            goal.timeout_code = code

    def _begin(self, goal: Goal, command: Callable[[], None] | None,
               failure: tuple[int, str] | None = None) -> Goal:
        """Make ``goal`` current (preempting the active one) and run ``command``."""
        with self._lock:
            # A later goal may have started while this one was planning: it wins.
            if self._current is not None and self._current.number > goal.number:
                self._notify(goal)
                self._finish(goal, Outcome.ABORTED, ERROR_NONE, "")
                return goal
            previous = self._current
            if previous is not None and previous.active:
                if previous.kind is goal.kind is Kind.FOLLOW:  # Nav2: new path, same clock
                    goal.progress_since_s = previous.progress_clock_s
                self._finish(previous, Outcome.ABORTED, ERROR_NONE, "")
            self._current = goal
            self._notify(goal)
            if failure is not None:
                self._robot.cancel()
                self._finish(goal, Outcome.ABORTED, *failure)
            elif command is not None:
                command()
        return goal

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

