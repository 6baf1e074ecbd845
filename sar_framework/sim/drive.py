"""Differential-drive robot: unicycle kinematics plus a waypoint path follower.

Time only advances through :meth:`DiffDrive.step`, so a simulation is deterministic and
runs at any rate (20-50 Hz steps are typical)::

    robot = DiffDrive(Pose2D(0.0, 0.0, 0.0))
    robot.follow(planner.plan((0.0, 0.0), (-3.0, 3.0)), goal_yaw=0.0)
    while robot.active:
        robot.step(0.05)
    robot.succeeded  # True: within 0.25 m and 0.25 rad of the goal

Control: a carrot-chasing (pure-pursuit style) heading controller. The robot aims at the
path point ``lookahead`` metres ahead of its projection on the path, turns in place while
that heading error exceeds ``rotate_threshold``, and otherwise drives with speed scaled by
``cos(error)`` and slowed near the goal. At the final position it turns in place to the
goal yaw. Commands never exceed the limits and never overshoot a target within one step.
"""

from __future__ import annotations

import enum
import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass

from sar_framework.sim.geometry import prune_to_nearest
from sar_framework.sim.world import Pose2D

Point = tuple[float, float]

PRUNE_SEARCH_M = 1.5
"""How far along a new path's start :meth:`DiffDrive.follow` looks for the point nearest the
robot (Nav2's controllers prune the plan up to it, searching about half the local costmap)."""


def normalize_angle(angle: float) -> float:
    """Wrap an angle to ``[-pi, pi)`` radians."""
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


@dataclass(frozen=True)
class DriveLimits:
    """Limits, tolerances and controller gains of a :class:`DiffDrive`.

    Attributes:
        max_linear: Maximum forward speed, m/s (the robot never reverses).
        max_angular: Maximum turn rate, rad/s.
        xy_tolerance: Goal position tolerance, metres (Nav2's ``xy_goal_tolerance``).
        yaw_tolerance: Goal heading tolerance, radians (Nav2's ``yaw_goal_tolerance``).
        lookahead: Distance along the path to the point the robot steers at, metres.
        heading_gain: Turn rate per radian of heading error, 1/s.
        rotate_threshold: Heading error above which the robot turns in place, radians.
        approach_gain: Speed per metre of remaining distance near the goal, 1/s.
        min_linear: Speed floor while driving, so the approach does not crawl, m/s.
        min_angular: Turn-rate floor while rotating, rad/s.
        arrive_distance: The follower aims this close to the goal before turning to the
            goal yaw, metres (tighter than ``xy_tolerance``).
        arrive_yaw: The final rotation stops within this, radians.
    """

    max_linear: float = 0.5
    max_angular: float = 1.0
    xy_tolerance: float = 0.25
    yaw_tolerance: float = 0.25
    lookahead: float = 0.3
    heading_gain: float = 2.5
    rotate_threshold: float = 0.6
    approach_gain: float = 1.0
    min_linear: float = 0.05
    min_angular: float = 0.1
    arrive_distance: float = 0.03
    arrive_yaw: float = 0.02

    def __post_init__(self) -> None:
        for name in ("max_linear", "max_angular", "xy_tolerance", "yaw_tolerance", "lookahead"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f"DriveLimits.{name}: expected a positive number, got {value!r}")


class Phase(enum.Enum):
    """What the follower is doing."""

    IDLE = "idle"
    """No goal yet, or cancelled."""
    DRIVING = "driving"
    """Following the path towards the goal position."""
    ROTATING = "rotating"
    """At the goal position, turning to the goal yaw."""
    ARRIVED = "arrived"
    """Goal reached; the robot is stopped."""
    SPINNING = "spinning"
    """Turning in place by a given angle (Nav2's spin behaviour)."""
    STRAIGHT = "straight"
    """Driving a given distance straight ahead or back (backup, drive_on_heading)."""


class DiffDrive:
    """A differential-drive robot that follows waypoint paths.

    Args:
        pose: Initial pose in the ``map`` frame.
        limits: Velocity limits, tolerances and gains (defaults: 0.5 m/s, 1.0 rad/s,
            0.25 m / 0.25 rad tolerances).
    """

    def __init__(self, pose: Pose2D | None = None, limits: DriveLimits | None = None) -> None:
        self.limits = limits or DriveLimits()
        self._x, self._y, self._yaw = 0.0, 0.0, 0.0
        if pose is not None:
            self.set_pose(pose)
        self._v = 0.0
        self._w = 0.0
        self._odometry = 0.0
        self._phase = Phase.IDLE
        self._path: list[Point] = []
        self._cumulative: list[float] = [0.0]  # arc length at each waypoint
        self._segment = 0
        self._goal_yaw = 0.0
        self._motion_left = 0.0  # radians (spin) or metres (straight) still to go
        self._motion_speed = 0.0  # signed rad/s or m/s of a spin or straight motion

    # ------------------------------------------------------------------ state

    @property
    def pose(self) -> Pose2D:
        """Current pose (yaw in ``[-pi, pi)``)."""
        return Pose2D(self._x, self._y, self._yaw)

    @property
    def velocity(self) -> tuple[float, float]:
        """The command applied by the last step: ``(linear m/s, angular rad/s)``."""
        return self._v, self._w

    @property
    def odometry(self) -> float:
        """Total distance driven since construction, metres."""
        return self._odometry

    @property
    def phase(self) -> Phase:
        """What the follower is doing."""
        return self._phase

    @property
    def active(self) -> bool:
        """True while a goal is being pursued (driving or rotating)."""
        return self._phase in (Phase.DRIVING, Phase.ROTATING, Phase.SPINNING, Phase.STRAIGHT)

    @property
    def motion_left(self) -> float:
        """Radians (spin) or metres (straight) left of the current motion."""
        return self._motion_left if self._phase in (Phase.SPINNING, Phase.STRAIGHT) else 0.0

    @property
    def destination(self) -> Pose2D | None:
        """The end of the path being followed, facing the goal yaw (None without a path)."""
        return Pose2D(*self._path[-1], self._goal_yaw) if self._path else None

    @property
    def succeeded(self) -> bool:
        """True once the goal has been reached within the tolerances."""
        return self._phase is Phase.ARRIVED

    def set_pose(self, pose: Pose2D) -> None:
        """Teleport the robot (e.g. on ``/initialpose``); a goal in progress continues."""
        self._x, self._y, self._yaw = float(pose.x), float(pose.y), normalize_angle(pose.yaw)

    # ------------------------------------------------------------------ goals

    def follow(self, path: Sequence[Point], goal_yaw: float) -> None:
        """Start following ``path`` and finish facing ``goal_yaw``.

        Args:
            path: Waypoints in metres; the last one is the goal. The path is followed from
                its point nearest the robot (within :data:`PRUNE_SEARCH_M` of its start;
                a path re-planned from a pose already passed is not driven back to),
                and the robot's position is prepended when it is not on the path.
            goal_yaw: Final heading, radians (any value; wrapped to ``[-pi, pi)``).

        Raises:
            ValueError: If ``path`` is empty or holds a non-finite value.
        """
        if not path:
            raise ValueError("follow(): path is empty")
        points = [(float(x), float(y)) for x, y in path]
        if not all(math.isfinite(v) for p in points for v in p) or not math.isfinite(goal_yaw):
            raise ValueError("follow(): path and goal_yaw must be finite")
        points = prune_to_nearest(points, (self._x, self._y), PRUNE_SEARCH_M)
        if math.dist(points[0], (self._x, self._y)) > 1e-3:
            points.insert(0, (self._x, self._y))
        if len(points) == 1:
            points.append(points[0])
        self._path = points
        self._cumulative = [0.0]
        for a, b in itertools.pairwise(points):
            self._cumulative.append(self._cumulative[-1] + math.dist(a, b))
        self._segment = 0
        self._goal_yaw = normalize_angle(goal_yaw)
        self._phase = Phase.DRIVING

    def spin(self, angle: float) -> None:
        """Turn in place by ``angle`` radians (signed, any size) at the angular limit."""
        self._start_motion(Phase.SPINNING, angle, self.limits.max_angular)

    def drive_straight(self, distance: float, speed: float) -> None:
        """Drive ``distance`` metres straight (negative: backwards) at ``|speed|`` m/s.

        The speed is capped by the linear limit.
        """
        self._start_motion(Phase.STRAIGHT, distance, min(abs(speed), self.limits.max_linear))

    def _start_motion(self, phase: Phase, amount: float, rate: float) -> None:
        if not (math.isfinite(amount) and math.isfinite(rate)) or rate <= 0.0:
            raise ValueError(f"{phase.value}: amount and speed must be finite, speed > 0")
        self._phase = phase
        self._path = []
        self._motion_left = abs(amount)
        self._motion_speed = math.copysign(rate, amount)

    def stand_still(self) -> None:
        """Apply no command this step (a stuck controller); the goal is kept."""
        self._v = self._w = 0.0

    def cancel(self) -> None:
        """Stop and drop the current goal."""
        self._phase = Phase.IDLE
        self._v = self._w = 0.0

    # ------------------------------------------------------------------ progress

    def distance_remaining(self) -> float:
        """Metres left along the path (0 when idle or arrived)."""
        if self._phase is Phase.DRIVING:
            s, offset = self._progress()
            return offset + self._cumulative[-1] - s
        if self._phase is Phase.ROTATING:
            return math.dist((self._x, self._y), self._path[-1])
        return 0.0

    def estimated_time_remaining(self) -> float:
        """Seconds to finish at full speed: the rest of the path plus the final turn."""
        if not self.active:
            return 0.0
        if self._phase in (Phase.SPINNING, Phase.STRAIGHT):
            return self._motion_left / abs(self._motion_speed)
        if self._phase is Phase.ROTATING:
            heading = self._yaw
        else:
            (ax, ay), (bx, by) = self._path[-2], self._path[-1]
            heading = math.atan2(by - ay, bx - ax) if (ax, ay) != (bx, by) else self._yaw
        turn = abs(normalize_angle(self._goal_yaw - heading))
        return self.distance_remaining() / self.limits.max_linear + turn / self.limits.max_angular

    def within_tolerance(self) -> bool:
        """True if the robot is within the xy and yaw tolerances of the current goal."""
        if not self._path:
            return False
        lim = self.limits
        return (
            math.dist((self._x, self._y), self._path[-1]) <= lim.xy_tolerance
            and abs(normalize_angle(self._goal_yaw - self._yaw)) <= lim.yaw_tolerance
        )

    # ------------------------------------------------------------------ simulation

    def step(self, dt: float, *, turn_only: bool = False) -> tuple[float, float]:
        """Advance the simulation by ``dt`` seconds.

        Args:
            dt: Time step, seconds (> 0).
            turn_only: Apply the command's turn but no linear speed (a robot held by
                another robot turns in place: its footprint does not move).

        Returns:
            The applied command ``(linear m/s, angular rad/s)``.

        Raises:
            ValueError: If ``dt`` is not a positive finite number.
        """
        if not (math.isfinite(dt) and dt > 0.0):
            raise ValueError(f"step(): dt must be a positive number of seconds, got {dt!r}")
        if self._phase is Phase.DRIVING:
            v, w = self._drive_command(dt)
        elif self._phase is Phase.ROTATING:
            v, w = self._rotate_command(dt)
        elif self._phase in (Phase.SPINNING, Phase.STRAIGHT):
            v, w = self._motion_command(dt)
        else:
            v, w = 0.0, 0.0
        v = 0.0 if turn_only else v
        self._integrate(v, w, dt)
        return v, w

    def _drive_command(self, dt: float) -> tuple[float, float]:
        lim = self.limits
        goal = self._path[-1]
        to_goal = math.dist((self._x, self._y), goal)
        s, _ = self._progress()
        on_last = self._segment == len(self._path) - 2
        goal_bearing = normalize_angle(math.atan2(goal[1] - self._y, goal[0] - self._x) - self._yaw)
        # Close enough, or within tolerance but already past the goal (do not turn back).
        if to_goal <= lim.arrive_distance or (
            on_last and to_goal <= lim.xy_tolerance and abs(goal_bearing) > math.pi / 2
        ):
            self._phase = Phase.ROTATING
            return self._rotate_command(dt)

        tx, ty = self._point_at(s + lim.lookahead)
        if math.dist((tx, ty), (self._x, self._y)) < 1e-6:
            tx, ty = goal
        error = normalize_angle(math.atan2(ty - self._y, tx - self._x) - self._yaw)
        w = self._turn_rate(error, dt)
        if abs(error) > lim.rotate_threshold:
            return 0.0, w
        speed = min(lim.max_linear, max(lim.approach_gain * to_goal, lim.min_linear))
        speed = min(speed * math.cos(error), to_goal / dt)  # never overshoot in one step
        return max(speed, 0.0), w

    def _rotate_command(self, dt: float) -> tuple[float, float]:
        error = normalize_angle(self._goal_yaw - self._yaw)
        if abs(error) <= self.limits.arrive_yaw:
            self._phase = Phase.ARRIVED
            return 0.0, 0.0
        return 0.0, self._turn_rate(error, dt, floor=self.limits.min_angular)

    def _motion_command(self, dt: float) -> tuple[float, float]:
        """Constant-rate spin or straight motion, never beyond what is left."""
        if self._motion_left <= 1e-9:
            self._phase = Phase.ARRIVED
            return 0.0, 0.0
        rate = math.copysign(min(abs(self._motion_speed), self._motion_left / dt),
                             self._motion_speed)
        self._motion_left = max(self._motion_left - abs(rate) * dt, 0.0)
        return (0.0, rate) if self._phase is Phase.SPINNING else (rate, 0.0)

    def _turn_rate(self, error: float, dt: float, floor: float = 0.0) -> float:
        """Proportional turn rate towards ``error``, limited and never overshooting in ``dt``."""
        lim = self.limits
        rate = min(max(lim.heading_gain * abs(error), floor), lim.max_angular, abs(error) / dt)
        return math.copysign(rate, error)

    def _integrate(self, v: float, w: float, dt: float) -> None:
        """Exact unicycle motion for a constant command over ``dt``."""
        yaw = self._yaw
        if abs(w) < 1e-9:
            self._x += v * dt * math.cos(yaw)
            self._y += v * dt * math.sin(yaw)
        else:
            self._x += v / w * (math.sin(yaw + w * dt) - math.sin(yaw))
            self._y -= v / w * (math.cos(yaw + w * dt) - math.cos(yaw))
        self._yaw = normalize_angle(yaw + w * dt)
        self._odometry += abs(v) * dt
        self._v, self._w = v, w

    # ------------------------------------------------------------------ path geometry

    def _project(self, segment: int) -> tuple[float, float, float]:
        """Project the robot on ``segment``: ``(t in [0, 1] unclamped, arc length, offset)``."""
        (ax, ay), (bx, by) = self._path[segment], self._path[segment + 1]
        dx, dy = bx - ax, by - ay
        length_sq = dx * dx + dy * dy
        t = ((self._x - ax) * dx + (self._y - ay) * dy) / length_sq if length_sq > 0 else 1.0
        tc = min(max(t, 0.0), 1.0)
        offset = math.hypot(self._x - (ax + tc * dx), self._y - (ay + tc * dy))
        return t, self._cumulative[segment] + tc * math.sqrt(length_sq), offset

    def _progress(self) -> tuple[float, float]:
        """Arc length of the robot's projection on the path and its distance from the path.

        As Nav2's controllers re-prune the plan every cycle, the current segment becomes the
        one nearest the robot among it and those starting within :data:`PRUNE_SEARCH_M`
        after the robot's projection (a tie goes to the later one). It only moves forward,
        and a robot that cuts across a corner of the path moves on with it.
        """
        last = len(self._path) - 2
        _, s, offset = self._project(self._segment)
        best = (self._segment, s, offset)
        horizon = s + PRUNE_SEARCH_M
        segment = self._segment + 1
        while segment <= last and self._cumulative[segment] <= horizon:
            _, s_next, offset_next = self._project(segment)
            if offset_next <= best[2]:
                best = (segment, s_next, offset_next)
            segment += 1
        self._segment, s, offset = best
        return s, offset

    def _point_at(self, s: float) -> Point:
        """The path point at arc length ``s`` (clamped to the path's ends)."""
        cumulative = self._cumulative
        s = min(max(s, 0.0), cumulative[-1])
        i = self._segment
        while i < len(self._path) - 2 and cumulative[i + 1] < s:
            i += 1
        length = cumulative[i + 1] - cumulative[i]
        t = (s - cumulative[i]) / length if length > 0 else 1.0
        (ax, ay), (bx, by) = self._path[i], self._path[i + 1]
        return ax + t * (bx - ax), ay + t * (by - ay)
