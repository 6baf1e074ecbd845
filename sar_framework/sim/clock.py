"""Simulated time: fixed physics steps paced against the wall clock by a speed factor.

:class:`SimClock` is plain Python (no ROS). Time is kept in integer nanoseconds so that
thousands of fixed steps never accumulate float error. The caller (the simulator's
physics loop) asks :meth:`SimClock.due_steps` how many steps the wall clock allows,
advances that many, then publishes ``/clock``::

    clock = SimClock(step_s=0.02, speed=20.0)
    clock.start(time.monotonic())
    while running:
        for _ in range(clock.due_steps(time.monotonic())):
            model.step(clock.step_s)
            clock.advance()
"""

from __future__ import annotations

import math

from sar_framework.sim.params import SPEED

NS_PER_S = 1_000_000_000


class SimClock:
    """Simulation time advanced in fixed steps, ``speed`` times faster than the wall clock.

    When the caller falls behind by more than ``max_lag_wall_s`` of wall time (a loaded
    machine), the backlog is dropped rather than run in a burst: simulated time then runs
    slower than ``speed`` for a moment instead of jumping (as Gazebo's real-time factor
    drops), so the world never moves on by seconds between two ``/clock`` messages.

    Args:
        step_s: Physics step, simulated seconds (e.g. 0.02 for 50 Hz).
        speed: Simulated seconds per wall second (1.0 real time, 20.0 twenty times faster);
            the rule is the ``speed`` parameter's (:data:`~.params.SPEED`).
        start_s: Simulated time at start, seconds.
        max_lag_wall_s: Largest backlog, in wall seconds at ``speed`` (so in simulated time
            ``max_lag_wall_s * speed``), that :meth:`due_steps` will report.

    Raises:
        ValueError: If ``step_s`` is not a positive finite number, or ``speed`` breaks
            :data:`~.params.SPEED`'s rule.
    """

    def __init__(
        self,
        step_s: float = 0.02,
        *,
        speed: float,
        start_s: float = 0.0,
        max_lag_wall_s: float = 0.2,
    ) -> None:
        if not (math.isfinite(step_s) and step_s > 0.0):
            raise ValueError(f"step_s must be a positive number, got {step_s!r}")
        self._step_ns = max(1, round(step_s * NS_PER_S))
        self._now_ns = round(start_s * NS_PER_S)
        self._max_lag_wall_s = max_lag_wall_s
        self._speed = 1.0
        self._anchor_wall: float | None = None
        self._anchor_ns = self._now_ns
        self._started_wall: float | None = None
        self._started_ns = self._now_ns
        self._dropped_steps = 0
        self.speed = speed

    # ------------------------------------------------------------------ properties

    @property
    def step_s(self) -> float:
        """The physics step, simulated seconds."""
        return self._step_ns / NS_PER_S

    @property
    def now_ns(self) -> int:
        """Current simulated time, nanoseconds."""
        return self._now_ns

    @property
    def now_s(self) -> float:
        """Current simulated time, seconds."""
        return self._now_ns / NS_PER_S

    @property
    def speed(self) -> float:
        """Simulated seconds per wall second."""
        return self._speed

    @speed.setter
    def speed(self, value: float) -> None:
        problem = SPEED.problem(value)
        if problem is not None:
            raise ValueError(f"speed {problem}")
        self._speed = float(value)
        self._anchor_wall = None  # re-anchor at the next due_steps() call

    @property
    def dropped_steps(self) -> int:
        """Steps skipped so far because the caller fell too far behind."""
        return self._dropped_steps

    # ------------------------------------------------------------------ pacing

    def start(self, wall_now: float) -> None:
        """Anchor simulated time to the wall clock.

        Args:
            wall_now: A monotonic wall time, seconds (``time.monotonic()``).
        """
        self._anchor_wall = wall_now
        self._anchor_ns = self._now_ns
        self._started_wall = wall_now
        self._started_ns = self._now_ns

    def due_steps(self, wall_now: float) -> int:
        """Return how many steps to advance now to keep up with ``speed``.

        Args:
            wall_now: A monotonic wall time, seconds.

        Returns:
            Steps due (0 when simulated time is ahead), at most ``max_lag_wall_s`` worth.
        """
        if self._anchor_wall is None:
            self._anchor_wall, self._anchor_ns = wall_now, self._now_ns
            if self._started_wall is None:
                self.start(wall_now)
            return 0
        target_ns = self._anchor_ns + (wall_now - self._anchor_wall) * self._speed * NS_PER_S
        # The epsilon absorbs float noise of wall-time differences (0.1 s -> 0.0999...).
        due = math.floor((target_ns - self._now_ns) / self._step_ns + 1e-6)
        most = max(1, math.floor(self._max_lag_wall_s * self._speed * NS_PER_S / self._step_ns
                                 + 1e-6))
        if due > most:
            # Forget the backlog: re-anchor so the target is `most` steps ahead of now.
            self._dropped_steps += due - most
            due = most
            self._anchor_wall = wall_now
            self._anchor_ns = self._now_ns + due * self._step_ns
            return due
        return max(due, 0)

    def hold(self) -> None:
        """Stop simulated time until the next :meth:`due_steps` call, without a catch-up.

        Used while the simulator computes something that takes no simulated time (a
        plan): the wall time spent is not owed afterwards.
        """
        self._anchor_wall = None

    def wall_until_next_step(self, wall_now: float) -> float:
        """Return wall seconds until the next step falls due (0 if one is due already).

        Args:
            wall_now: A monotonic wall time, seconds.
        """
        if self._anchor_wall is None:
            return 0.0
        next_ns = self._now_ns + self._step_ns - self._anchor_ns
        due_wall = self._anchor_wall + next_ns / NS_PER_S / self._speed
        return max(due_wall - wall_now, 0.0)

    def advance(self, steps: int = 1) -> int:
        """Advance simulated time by ``steps`` physics steps.

        Args:
            steps: How many steps.

        Returns:
            The new simulated time, nanoseconds.
        """
        self._now_ns += steps * self._step_ns
        return self._now_ns

    def real_time_factor(self, wall_now: float) -> float:
        """Return simulated seconds per wall second since :meth:`start` (0 before start).

        Args:
            wall_now: A monotonic wall time, seconds.
        """
        if self._started_wall is None or wall_now <= self._started_wall:
            return 0.0
        return (self._now_ns - self._started_ns) / NS_PER_S / (wall_now - self._started_wall)


def split_ns(stamp_ns: int) -> tuple[int, int]:
    """Split nanoseconds into ``(sec, nanosec)`` as ``builtin_interfaces/Time`` wants.

    Args:
        stamp_ns: Non-negative time, nanoseconds.
    """
    return stamp_ns // NS_PER_S, stamp_ns % NS_PER_S
