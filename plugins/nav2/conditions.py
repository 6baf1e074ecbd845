"""Nav2's conditions.

GoalUpdated, GlobalUpdatedGoal, GoalReached, IsStuck, TimeExpired, PathExpiringTimer,
WouldAControllerRecoveryHelp, WouldAPlannerRecoveryHelp.

Nav2 Jazzy's semantics. "Active" is BT.CPP's ``isStatusActive``: the condition was ticked
since its parent last reset it to IDLE (its
:func:`~sar_framework.engine.nodes.controls.base.bt_status` is not INVALID). Times are the ROS
node's clock (simulated with ``use_sim_time``); without a node, the monotonic clock.
"""

from __future__ import annotations

from collections import deque
from typing import Any

import py_trees
from py_trees.blackboard import Blackboard
from py_trees.common import Status

from sar_framework.engine.nodes.controls.base import bt_status
from sar_framework.engine.plugin import leaf
from sar_framework.engine.ports import InputPort

from ._common import navigator_setting, node_now, optional_input, planar_distance
from ._tf import robot_pose, tf_buffer

POSE = "geometry_msgs/msg/PoseStamped"
PATH = "nav_msgs/msg/Path"
_GOAL = InputPort("goal", POSE, optional=True,
                  description="Destination to check; the blackboard's \"{goal}\" if not given.")
_GOALS = InputPort("goals", list, optional=True,
                   description="Vector of goals to check; the blackboard's \"{goals}\" if not "
                               "given.")


class Nav2Condition(py_trees.behaviour.Behaviour):
    """A condition with ports, the node's clock and BT.CPP's "was it active" flag.

    Args:
        name: The behaviour's name.
        ports: The leaf's ports.
    """

    def __init__(self, name: str, *, ports: Any) -> None:
        super().__init__(name=name)
        self.ports = ports
        self.node: Any = None
        self.was_active = False

    def setup(self, **kwargs: Any) -> None:
        """Keep the ROS node when one is given (its clock, TF, parameters)."""
        self.node = kwargs.get("node", self.node)

    def initialise(self) -> None:
        """Note whether the previous tick left a status (BT.CPP: the node is active)."""
        self.was_active = bt_status(self) != Status.INVALID

    def now(self) -> float:
        """Seconds on the node's clock."""
        return node_now(self.node)

    def input_or_blackboard(self, name: str) -> Any:
        """BT.CPP's ``getInputOrBlackboard``: the port, else the root entry of that name."""
        ports = self.ports
        if ports is not None and (ports.key(name) is not None or name in ports.literals):
            return optional_input(ports, name)
        return Blackboard.storage.get(f"/{name}")


class _GoalWatch(Nav2Condition):
    def read(self) -> tuple[Any, Any]:
        return self.input_or_blackboard("goal"), self.input_or_blackboard("goals")

    def changed(self) -> bool:
        """Whether goal or goals differ from those seen last; remember the new ones."""
        goal, goals = self.read()
        if goal != self.seen[0] or goals != self.seen[1]:
            self.seen = (goal, goals)
            return True
        return False


@leaf(condition=True, ports=[_GOAL, _GOALS])
class GoalUpdated(_GoalWatch):
    """Nav2's GoalUpdated: SUCCESS when goal or goals changed since this node became active."""

    seen: tuple[Any, Any] = (None, None)

    def update(self) -> Status:
        """FAILURE on an active period's first tick (goals noted), then SUCCESS on change."""
        if not self.was_active:
            self.seen = self.read()
            return Status.FAILURE
        return Status.SUCCESS if self.changed() else Status.FAILURE


@leaf(condition=True, ports=[_GOAL, _GOALS])
class GlobalUpdatedGoal(_GoalWatch):
    """Nav2's GlobalUpdatedGoal: like GoalUpdated, but remembering across resets."""

    seen: tuple[Any, Any] = (None, None)
    first_time = True

    def update(self) -> Status:
        """FAILURE the very first tick; then SUCCESS whenever goal or goals changed."""
        if self.first_time:
            self.first_time = False
            self.seen = self.read()
            return Status.FAILURE
        return Status.SUCCESS if self.changed() else Status.FAILURE


@leaf(condition=True, ports=[
    InputPort("goal", POSE, optional=True, description="Destination to check."),
    InputPort("global_frame", str, optional=True, description="Reference frame."),
    InputPort("robot_base_frame", str, optional=True, description="Robot base frame. If not "
              "provided, uses the BT Navigator's `robot_base_frame` parameter value."),
])
class GoalReached(Nav2Condition):
    """Nav2's GoalReached: SUCCESS when the robot is within ``goal_reached_tol`` of the goal.

    The tolerance is the node's ``goal_reached_tol`` parameter when declared, else 0.25 m
    (Nav2 Jazzy's default); the robot's pose is TF's ``global_frame`` -> ``robot_base_frame``.
    """

    def setup(self, **kwargs: Any) -> None:
        """Keep the node and start listening to TF (Nav2's shared ``tf_buffer``)."""
        super().setup(**kwargs)
        if self.node is not None:
            tf_buffer(self.node)

    def tolerance(self) -> float:
        """``goal_reached_tol`` (m)."""
        if self.node is not None and self.node.has_parameter("goal_reached_tol"):
            return float(self.node.get_parameter("goal_reached_tol").value)
        return 0.25

    def robot(self) -> Any:
        """The robot's pose, or None."""
        frame = (optional_input(self.ports, "global_frame")
                 or navigator_setting(self.node, "global_frame"))
        base = (optional_input(self.ports, "robot_base_frame")
                or navigator_setting(self.node, "robot_base_frame"))
        return robot_pose(self.node, frame, base) if self.node is not None else None

    def update(self) -> Status:
        """SUCCESS within the tolerance; FAILURE otherwise or without a pose or a goal."""
        goal, robot = optional_input(self.ports, "goal"), self.robot()
        if goal is None or robot is None:
            self.feedback_message = "no goal" if goal is None else "robot pose not available"
            return Status.FAILURE
        distance = planar_distance(goal, robot)
        self.feedback_message = f"{distance:.2f} m from the goal"
        return Status.SUCCESS if distance <= self.tolerance() else Status.FAILURE


class Deceleration:
    """Nav2 IsStuck's test: the last two odometry samples decelerate beyond the brake limit.

    Args:
        history: Samples kept (Nav2: 10).
        brake_accel_limit: m/s²; stuck below it (Nav2: -10).
    """

    def __init__(self, history: int = 10, brake_accel_limit: float = -10.0) -> None:
        self.samples: deque[tuple[float, float]] = deque(maxlen=history)
        self.limit = brake_accel_limit
        self.accel = 0.0
        self.stuck = False

    def add(self, stamp_s: float, speed_x: float) -> None:
        """Add one sample (stamp in seconds, forward speed in m/s) and update ``stuck``."""
        self.samples.append((stamp_s, speed_x))
        if len(self.samples) > 2:
            (t0, v0), (t1, v1) = self.samples[-2], self.samples[-1]
            if t1 > t0:
                self.accel = (v1 - v0) / (t1 - t0)
        self.stuck = self.accel < self.limit


@leaf(condition=True)
class IsStuck(Nav2Condition):
    """Nav2's IsStuck: SUCCESS while odometry shows a deceleration beyond -10 m/s².

    The odometry topic is the navigator's ``odom_topic`` (a parameter of the node when
    declared; else ``odom``).
    """

    def __init__(self, name: str, *, ports: Any = None) -> None:
        super().__init__(name, ports=ports)
        self.watch = Deceleration()
        self._subscription: Any = None

    def setup(self, **kwargs: Any) -> None:
        """Subscribe to the navigator's ``odom_topic`` on the node."""
        super().setup(**kwargs)
        if self.node is not None and self._subscription is None:
            from nav_msgs.msg import Odometry

            topic = navigator_setting(self.node, "odom_topic")
            self._subscription = self.node.create_subscription(
                Odometry, topic, self.on_odometry, 10)

    def on_odometry(self, message: Any) -> None:
        """Feed one odometry message to the test."""
        stamp = message.header.stamp
        self.watch.add(stamp.sec + stamp.nanosec * 1e-9, message.twist.twist.linear.x)

    def update(self) -> Status:
        """SUCCESS when stuck (a stuck condition was detected), FAILURE when free."""
        self.feedback_message = "Robot got stuck!" if self.watch.stuck else "Robot is free"
        return Status.SUCCESS if self.watch.stuck else Status.FAILURE

    def shutdown(self) -> None:
        """Destroy the subscription."""
        if self._subscription is not None:
            self.node.destroy_subscription(self._subscription)
            self._subscription = None


@leaf(condition=True, ports=[InputPort("seconds", float, default=1.0,
                       description="The time passed to return success (s).")])
class TimeExpired(Nav2Condition):
    """Nav2's TimeExpired: SUCCESS once every ``seconds`` of an active period, else FAILURE."""

    start = 0.0

    def update(self) -> Status:
        """FAILURE on the first tick (the timer starts) and until ``seconds`` passed."""
        now = self.now()
        if not self.was_active:
            self.start = now
            return Status.FAILURE
        if now - self.start < float(self.ports.get("seconds")):
            return Status.FAILURE
        self.start = now
        return Status.SUCCESS


@leaf(condition=True, ports=[
    InputPort("seconds", float, default=1.0, description="Time to check if expired."),
    InputPort("path", PATH, optional=True,
              description="Check if path has been updated to enable timer reset."),
])
class PathExpiringTimer(Nav2Condition):
    """Nav2's PathExpiringTimer: SUCCESS every ``seconds`` without a new ``path``."""

    first_time = True
    start = 0.0
    period = 1.0
    previous: Any = None

    def update(self) -> Status:
        """FAILURE until ``seconds`` passed since the start or the last new path."""
        now = self.now()
        path = optional_input(self.ports, "path")
        if self.first_time:
            self.first_time = False
            self.period = float(self.ports.get("seconds"))
            self.previous, self.start = path, now
            return Status.FAILURE
        if path is not None and (self.previous is None or (
                path is not self.previous and path != self.previous)):
            self.previous, self.start = path, now
        if now - self.start < self.period:
            return Status.FAILURE
        self.start = now
        return Status.SUCCESS


#: Nav2 Jazzy's codes a recovery may help with: (module, action, code names).
CONTROLLER_CODES = (("FollowPath", ("UNKNOWN", "PATIENCE_EXCEEDED", "FAILED_TO_MAKE_PROGRESS",
                                    "NO_VALID_CONTROL")),)
PLANNER_CODES = (("ComputePathToPose", ("UNKNOWN", "NO_VALID_PATH", "TIMEOUT")),
                 ("ComputePathThroughPoses", ("UNKNOWN", "NO_VALID_PATH", "TIMEOUT")))


def error_codes(table: tuple[tuple[str, tuple[str, ...]], ...]) -> frozenset[int]:
    """The codes a table names, read from ``nav2_msgs``' action results."""
    import nav2_msgs.action as actions

    return frozenset(int(getattr(getattr(actions, action).Result, code))
                     for action, codes in table for code in codes)


_CODE_PORTS = [
    InputPort("error_code", int, optional=True, description="The active error code to "
              "compare against."),
    InputPort("error_codes_to_check", list, optional=True, description="Not read: as in "
              "Nav2 Jazzy, the set is fixed (see the class description)."),
]


class _RecoveryHelp(Nav2Condition):
    TABLE: tuple[tuple[str, tuple[str, ...]], ...] = ()
    codes: frozenset[int] | None = None

    def update(self) -> Status:
        """SUCCESS when ``error_code`` is one of the codes, else FAILURE."""
        if self.codes is None:
            self.codes = error_codes(self.TABLE)
        code = optional_input(self.ports, "error_code")
        helps = code is not None and int(code) in self.codes
        verdict = "may" if helps else "would not"
        self.feedback_message = f"error code {code}: recovery {verdict} help"
        return Status.SUCCESS if helps else Status.FAILURE


@leaf(condition=True, ports=_CODE_PORTS)
class WouldAControllerRecoveryHelp(_RecoveryHelp):
    """Nav2's WouldAControllerRecoveryHelp: a controller error a recovery may fix.

    FollowPath's UNKNOWN, PATIENCE_EXCEEDED, FAILED_TO_MAKE_PROGRESS or NO_VALID_CONTROL.
    """

    TABLE = CONTROLLER_CODES


@leaf(condition=True, ports=_CODE_PORTS)
class WouldAPlannerRecoveryHelp(_RecoveryHelp):
    """Nav2's WouldAPlannerRecoveryHelp: the planners' UNKNOWN, NO_VALID_PATH or TIMEOUT."""

    TABLE = PLANNER_CODES
