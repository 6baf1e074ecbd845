"""Nav2's decorators that read the robot: DistanceController, SpeedController, GoalUpdater.

Nav2 Jazzy's behaviour (``nav2_behavior_tree/plugins/decorator``), on data given as
callables the tree's context gives (:mod:`.robot_context`), so no ROS is imported here.
"Starting" is BT.CPP's ``!isStatusActive``: the node was IDLE (reset by its parent).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from typing import Any

from py_trees.common import Status

from sar_framework.engine.building.control_build import bound_variables, clock_of
from sar_framework.engine.kind_plugin import decorator_kind, node_kind
from sar_framework.engine.nodes.control_kinds import port_attr
from sar_framework.engine.nodes.controls.base import (
    Behaviour,
    BtDecorator,
    Clock,
    Outcome,
    Steps,
    bt_status,
)
from sar_framework.engine.nodes.kind_model import Attr, AttrType
from sar_framework.engine.ports import Direction
from sar_framework.engine.spec import NodeSpec
from sar_framework.engine.variables import Variables, value_or_none

from .decorators import POSE, goal_ports, goal_variables
from .robot_context import PoseSource, pose_source, speed_source, update_source


def _number(name: str, default: float, text: str) -> Attr:
    return Attr(name, AttrType.NUMBER, default=default, minimum=0.0, description=text)


def _frame(name: str, text: str) -> Attr:
    return Attr(name, AttrType.STRING, default="", description=text)


def _distance(node: NodeSpec, children: list[Any], context: Mapping[str, Any]) -> Any:
    return DistanceController(node.name, children[0], pose_source(context), **node.attrs)


def _speed(node: NodeSpec, children: list[Any], context: Mapping[str, Any]) -> Any:
    attrs = {k: v for k, v in node.attrs.items() if k not in ("goal", "goals")}
    return SpeedController(node.name, children[0], speed_source(context), goal_variables(node),
                           goal="goal", goals="goals", clock=clock_of(context), **attrs)


def _goal_updater(node: NodeSpec, children: list[Any], context: Mapping[str, Any]) -> Any:
    return GoalUpdater(node.name, children[0], update_source(context),
                       bound_variables(node, "input_goal", "output_goal"),
                       input_goal="input_goal", output_goal="output_goal")


@node_kind(decorator_kind(
    "DistanceController", "Nav2: tick the child each time the robot travelled distance metres "
    "(and on the first tick, and while it runs); else RUNNING.",
    _number("distance", 1.0, "Metres travelled between ticks of the child."),
    _frame("global_frame", "Reference frame ('': the navigator's, map)."),
    _frame("robot_base_frame", "Robot frame ('': the navigator's, base_link).")),
    build=_distance)
class DistanceController(BtDecorator):
    """Nav2 ``DistanceController``: tick the child each time the robot travelled ``distance``.

    The child is ticked on the first tick, while it runs, and whenever the robot is
    ``distance`` metres from where the child last succeeded (or from the start); else
    RUNNING. Without a robot pose, FAILURE.

    Args:
        name: The behaviour's name.
        child: The decorated behaviour.
        pose: The robot's pose source.
        distance: Metres.
        global_frame: Reference frame ("": the navigator's).
        robot_base_frame: Robot frame ("": the navigator's).
    """

    def __init__(self, name: str, child: Behaviour, pose: PoseSource, *, distance: float = 1.0,
                 global_frame: str = "", robot_base_frame: str = "") -> None:
        super().__init__(name, child)
        self.pose = pose
        self.distance = distance
        self.frames = (global_frame, robot_base_frame)
        self.start: tuple[float, float] | None = None
        self.first = True

    def decorate(self) -> Steps:
        """The child's outcome when it is ticked, else RUNNING; FAILURE without a pose."""
        if self.was_idle:
            self.start = self.pose(*self.frames)
            self.first = True
            if self.start is None:
                self.feedback_message = "robot pose not available"
                return Outcome.FAILURE
        here = self.pose(*self.frames)
        if here is None or self.start is None:
            self.feedback_message = "robot pose not available"
            return Outcome.FAILURE
        travelled = math.dist(here, self.start)
        if self.first or bt_status(self.decorated) == Status.RUNNING or \
                travelled >= self.distance:
            self.first = False
            result = yield from self.tick_child()
            if result is Outcome.SUCCESS:
                self.start = here
            return result
        return Outcome.RUNNING


@node_kind(decorator_kind(
    "SpeedController", "Nav2: tick the child at a rate from min_rate to max_rate as the "
    "robot's speed goes from min_speed to max_speed; else RUNNING.",
    _number("min_rate", 0.1, "Hz at min_speed and below."),
    _number("max_rate", 1.0, "Hz at max_speed and above."),
    _number("min_speed", 0.0, "m/s."), _number("max_speed", 0.5, "m/s."),
    *goal_ports(" (a new goal ticks the child)")), build=_speed)
class SpeedController(BtDecorator):
    """Nav2 ``SpeedController``: tick the child at a rate that grows with the robot's speed.

    The rate goes linearly from ``min_rate`` at ``min_speed`` to ``max_rate`` at
    ``max_speed`` (clamped); the child is ticked on the first tick, when the goal changed,
    while it runs, and once a period passed (the period is then updated from the speed).
    Starting and a new goal both restart the period at ``1 / max_rate``.

    Args:
        name: The behaviour's name.
        child: The decorated behaviour.
        speed: The robot's speed source (None: unknown, taken as 0).
        variables: Reads the goal and goals.
        goal: The goal variable.
        goals: The goal list variable.
        clock: Seconds.
        min_rate: Hz.
        max_rate: Hz.
        min_speed: m/s.
        max_speed: m/s.
    """

    def __init__(self, name: str, child: Behaviour, speed: Callable[[], float | None],
                 variables: Variables, *, goal: str = "goal", goals: str = "goals",
                 clock: Clock, min_rate: float = 0.1, max_rate: float = 1.0,
                 min_speed: float = 0.0, max_speed: float = 0.5) -> None:
        super().__init__(name, child)
        if not 0 < min_rate <= max_rate or not 0 <= min_speed <= max_speed:
            raise ValueError(f"SpeedController '{name}': need 0 < min_rate <= max_rate and "
                             "0 <= min_speed <= max_speed")
        self.speed = speed
        self.variables = variables
        self.names = (goal, goals)
        self.clock = clock
        self.rates = (min_rate, max_rate)
        self.speeds = (min_speed, max_speed)
        self.period = 1.0 / max_rate
        self.start = 0.0
        self.first = True
        self.seen: tuple[Any, Any] = (None, None)

    def rate(self, speed: float) -> float:
        """The tick rate (Hz) for a speed."""
        (low_rate, high_rate), (low, high) = self.rates, self.speeds
        if speed <= low or high == low:
            return low_rate
        if speed >= high:
            return high_rate
        return low_rate + (high_rate - low_rate) * (speed - low) / (high - low)

    def decorate(self) -> Steps:
        """The child's outcome when it is ticked, else RUNNING."""
        now = self.clock()
        goals = tuple(value_or_none(self.variables, n) for n in self.names)
        if self.was_idle or goals != self.seen:  # a new goal restarts at max_rate too
            self.period, self.start, self.first = 1.0 / self.rates[1], now, True
            self.seen = goals
        elapsed = now - self.start
        if self.first or bt_status(self.decorated) == Status.RUNNING or elapsed >= self.period:
            self.first = False
            if elapsed >= self.period:
                self.period = 1.0 / self.rate(self.speed() or 0.0)
                self.start = now
            return (yield from self.tick_child())
        return Outcome.RUNNING


def _stamp(message: Any) -> float:
    stamp = message.header.stamp
    return stamp.sec + stamp.nanosec * 1e-9


@node_kind(decorator_kind(
    "GoalUpdater", "Nav2: output_goal is input_goal, or a newer goal received on the "
    "goal_update topic; then tick the child.",
    port_attr("input_goal", POSE, "The original goal: '{name}'."),
    port_attr("output_goal", POSE, "The goal to use (input_goal or a newer one): '{name}'.",
              direction=Direction.OUTPUT)), build=_goal_updater)
class GoalUpdater(BtDecorator):
    """Nav2 ``GoalUpdater``: ``output_goal`` is the newest of ``input_goal`` and a goal update.

    A goal received on the update source replaces the input goal when its stamp is newer
    (one without a stamp is ignored, with a note); then the child is ticked.

    Args:
        name: The behaviour's name.
        child: The decorated behaviour.
        update: The last goal update (None: none).
        variables: Reads ``input_goal``, writes ``output_goal``.
        input_goal: The input variable.
        output_goal: The output variable.
    """

    def __init__(self, name: str, child: Behaviour, update: Callable[[], Any],
                 variables: Variables, *, input_goal: str, output_goal: str) -> None:
        super().__init__(name, child)
        self.update_source = update
        self.variables = variables
        self.names = (input_goal, output_goal)

    def decorate(self) -> Steps:
        """Write ``output_goal``, then tick the child."""
        goal = value_or_none(self.variables, self.names[0])
        received = self.update_source()
        if received is not None:
            if _stamp(received) == 0.0:
                self.feedback_message = "the received goal has no timestamp: ignored"
            elif goal is None or _stamp(received) > _stamp(goal):
                goal = received
            else:
                self.feedback_message = "the received goal is older than the current one"
        if goal is not None:
            self.variables.set(self.names[1], goal)
        return (yield from self.tick_child())
