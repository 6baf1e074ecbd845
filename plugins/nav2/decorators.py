"""Nav2's ROS-free decorators (``nav2_behavior_tree``, Jazzy), each with its declaration.

RateController, SingleTrigger, GoalUpdatedController, PathLongerOnApproach (the last two
read messages from the blackboard without importing them: fields by name).

RateController, SingleTrigger and GoalUpdatedController restart when their status was reset
to IDLE by their parent (BT.CPP's ``isStatusActive``), which is how Nav2 trees re-arm them
between runs.

Their ``goal`` and ``goals`` (optional: unbound, the root's entry of that name is read, as
Nav2's ``getInputOrBlackboard``) and ``path`` are ports, typed as Nav2's palette types
them (by name: no ROS message is imported).
"""

from __future__ import annotations

import itertools
import math
import time
from collections.abc import Mapping
from typing import Any

from py_trees.common import Status

from sar_framework.engine.building.control_build import bound_variables
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
from sar_framework.engine.ports import NO_DEFAULT
from sar_framework.engine.spec import NodeSpec
from sar_framework.engine.variables import BlackboardVariables, Variables, value_or_none

#: The ROS message types of the decorators' ports (by name: no ROS is imported).
POSE, PATH = "geometry_msgs/msg/PoseStamped", "nav_msgs/msg/Path"


def goal_ports(text: str = "") -> tuple[Attr, Attr]:
    """Nav2's ``goal`` and ``goals`` inputs, read with ``getInputOrBlackboard``."""
    return (port_attr("goal", POSE, "Destination to check: '{name}'; unbound, the root's "
                      f"'goal' entry{text}.", optional=True),
            port_attr("goals", "list", "Vector of goals to check: '{name}'; unbound, the "
                      "root's 'goals' entry.", optional=True))


def goal_variables(node: NodeSpec) -> BlackboardVariables:
    """``goal`` and ``goals`` as bound, else the root's entries (``getInputOrBlackboard``)."""
    keys: dict[str, str] = {}
    for name in ("goal", "goals"):
        binding = node.bindings.get(name)
        if binding is None or (binding.key is None and binding.value is NO_DEFAULT):
            keys[name] = f"/{name}"
        elif binding.key is not None:
            keys[name] = binding.key
    return BlackboardVariables(node.name, keys, [])


def _goal_updated(node: NodeSpec, children: list[Any], context: Mapping[str, Any]) -> Any:
    return GoalUpdatedController(node.name, children[0], "goal", "goals",
                                 goal_variables(node))


def _path_longer(node: NodeSpec, children: list[Any], context: Mapping[str, Any]) -> Any:
    return PathLongerOnApproach(
        node.name, children[0], "path", bound_variables(node, "path"),
        prox_len=node.attrs["prox_len"], length_factor=node.attrs["length_factor"])


@node_kind(decorator_kind(
    "RateController", "Nav2: tick the child at most hz times a second (a running child every "
    "tick).",
    Attr("hz", AttrType.NUMBER, default=10.0, exclusive_minimum=0.0,
         description="Child ticks per second."), context=("clock",)))
class RateController(BtDecorator):
    """Nav2 ``RateController``: tick the child at most ``hz`` times a second.

    Between permitted ticks it returns RUNNING without ticking the child; a running
    child is ticked every time; a success restarts the period.

    Args:
        name: The behaviour's name.
        child: The decorated behaviour.
        hz: Ticks per second the child gets.
        clock: Returns the time in seconds.
    """

    def __init__(self, name: str, child: Behaviour, hz: float = 10.0,
                 clock: Clock = time.monotonic) -> None:
        if hz <= 0:
            raise ValueError(f"RateController '{name}': hz must be > 0, got {hz}")
        super().__init__(name, child)
        self.hz = hz
        self.clock = clock
        self.period = 1.0 / hz
        self.start = 0.0
        self.first = False

    def decorate(self) -> Steps:
        """Tick the child on the first tick, while it runs, or once the period passed."""
        if self.was_idle:
            self.period = 1.0 / self.hz
            self.start = self.clock()
            self.first = True
        if (self.first or bt_status(self.decorated) == Status.RUNNING
                or self.clock() - self.start >= self.period):
            self.first = False
            result = yield from self.tick_child()
            if result is Outcome.SUCCESS:
                self.start = self.clock()
            return result
        return Outcome.RUNNING


@node_kind(decorator_kind("SingleTrigger", "Nav2: tick the child to one completion, then "
                          "FAILURE until the node is reset."))
class SingleTrigger(BtDecorator):
    """Nav2 ``SingleTrigger``: tick the child to one completion, then FAILURE until reset.

    Args:
        name: The behaviour's name.
        child: The decorated behaviour.
    """

    def __init__(self, name: str, child: Behaviour) -> None:
        super().__init__(name, child)
        self.first = True

    def decorate(self) -> Steps:
        """The child's result until it completed once in this activation, then FAILURE."""
        if self.was_idle:
            self.first = True
        if not self.first:
            return Outcome.FAILURE
        result = yield from self.tick_child()
        if result.completed:
            self.first = False
        return result


@node_kind(decorator_kind("GoalUpdatedController", "Nav2: tick the child when goal or goals "
                          "changed (starting counts) and while it runs; else RUNNING.",
                          *goal_ports()), build=_goal_updated)
class GoalUpdatedController(BtDecorator):
    """Nav2 ``GoalUpdatedController``: tick the child when the goal changed, or while it runs.

    Starting (from IDLE) counts as a change. Between changes, with the child not running,
    it returns RUNNING without ticking it.

    Args:
        name: The behaviour's name.
        child: The decorated behaviour.
        goal: The variable holding the goal.
        goals: The variable holding the goal list.
        variables: Reads them.
    """

    def __init__(self, name: str, child: Behaviour, goal: str, goals: str,
                 variables: Variables) -> None:
        super().__init__(name, child)
        self.names = (goal, goals)
        self.variables = variables
        self.seen: tuple[Any, Any] = (None, None)
        self.updated = True

    def decorate(self) -> Steps:
        """The child's outcome when it is ticked, else RUNNING."""
        current = tuple(value_or_none(self.variables, n) for n in self.names)
        if self.was_idle or current != self.seen:  # starting counts as a change
            self.seen, self.updated = current, True
        if bt_status(self.decorated) == Status.RUNNING or self.updated:
            self.updated = False
            return (yield from self.tick_child())
        return Outcome.RUNNING


def path_length(path: Any) -> float:
    """The length of a ``nav_msgs/Path`` (duck-typed: ``poses[i].pose.position``)."""
    points = [(p.pose.position.x, p.pose.position.y, p.pose.position.z) for p in path.poses]
    return sum(math.dist(a, b) for a, b in itertools.pairwise(points))


@node_kind(decorator_kind(
    "PathLongerOnApproach", "Nav2: tick the child when a new path to the same goal is "
    "length_factor times longer while the old one was shorter than prox_len; else SUCCESS.",
    port_attr("path", PATH, "The path created by the planner: '{name}'."),
    Attr("prox_len", AttrType.NUMBER, default=3.0, minimum=0.0,
         description="Proximity length (m) for the path to be longer on approach."),
    Attr("length_factor", AttrType.NUMBER, default=2.0, minimum=0.0,
         description="How many times longer the new path must be.")), build=_path_longer)
class PathLongerOnApproach(BtDecorator):
    """Nav2 ``PathLongerOnApproach``: tick the child when a new path is much longer near the goal.

    The child is ticked when the path was replaced by one to the same goal position
    (another number of poses), the old one was shorter than ``prox_len`` and the new one
    is more than ``length_factor`` times as long, and not on the first tick of a goal;
    otherwise SUCCESS. ``path`` is remembered after every tick that does not leave the
    child running.

    Args:
        name: The behaviour's name.
        child: The decorated behaviour.
        path: The variable holding the path.
        variables: Reads it.
        prox_len: Metres.
        length_factor: How much longer counts.
    """

    def __init__(self, name: str, child: Behaviour, path: str, variables: Variables, *,
                 prox_len: float = 3.0, length_factor: float = 2.0) -> None:
        super().__init__(name, child)
        self.path_name = path
        self.variables = variables
        self.prox_len = prox_len
        self.length_factor = length_factor
        self.old: Any = None
        self.first_time = True

    def decorate(self) -> Steps:
        """The child's outcome when it is ticked, else SUCCESS."""
        new = value_or_none(self.variables, self.path_name)
        old_poses = list(getattr(self.old, "poses", []))
        new_poses = list(getattr(new, "poses", []))
        if not self.first_time and (not old_poses or not new_poses
                                    or old_poses[-1].pose != new_poses[-1].pose):
            self.first_time = True
        updated = (bool(old_poses) and bool(new_poses) and len(new_poses) != len(old_poses)
                   and old_poses[-1].pose.position == new_poses[-1].pose.position)
        if (updated and path_length(self.old) < self.prox_len and not self.first_time
                and path_length(new) > self.length_factor * path_length(self.old)):
            result = yield from self.tick_child()
            if result.completed:
                self.old = new
                self.reset_child()
            return result
        self.old = new
        self.first_time = False
        return Outcome.SUCCESS
