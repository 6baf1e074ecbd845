"""Nav2's DistanceController, SpeedController and GoalUpdater, ticked in py_trees (no ROS).

Behaviour read from ``nav2_behavior_tree/plugins/decorator`` (Jazzy); the robot's pose,
speed and goal updates are callables given in the build context
(:mod:`sar_plugins.nav2.robot_context`).
"""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import pytest
from engine.script_variables import DictVariables
from engine.scripted_leaves import Clock, Log, Scripted, tick
from py_trees.blackboard import Blackboard
from py_trees.common import Status
from sar_plugins.nav2.controls import PipelineSequence
from sar_plugins.nav2.robot_context import (
    GOAL_UPDATE_KEY,
    ROBOT_POSE_KEY,
    ROBOT_SPEED_KEY,
)
from sar_plugins.nav2.robot_decorators import (
    DistanceController,
    GoalUpdater,
    SpeedController,
)

from sar_framework.engine.api import load_tree
from sar_framework.engine.building.control_build import CLOCK_KEY
from sar_framework.engine.registry import Registry


class Robot:
    def __init__(self) -> None:
        self.xy: tuple[float, float] | None = (0.0, 0.0)
        self.frames: list[tuple[str, str]] = []
        self.started = 0

    def start(self) -> None:
        self.started += 1

    def __call__(self, frame: str, base: str) -> tuple[float, float] | None:
        self.frames.append((frame, base))
        return self.xy


def pipeline(decorator: object, log: Log) -> PipelineSequence:
    """As in Nav2's trees: beside a running FollowPath."""
    return PipelineSequence("P", [decorator, Scripted("Follow", ["RUNNING"] * 20, log)])


def plans(log: Log) -> list[str]:
    return [v for v in log.visits if v.startswith("Plan")]


def test_distance_controller_ticks_the_child_every_distance() -> None:
    log, robot = Log(), Robot()
    node = DistanceController("D", Scripted("Plan", ["SUCCESS"] * 5, log), robot, distance=1.0,
                              global_frame="map")
    root = pipeline(node, log)
    tick(root)
    assert plans(log) == ["Plan SUCCESS"]  # the first tick
    robot.xy = (0.6, 0.0)
    tick(root)
    assert len(plans(log)) == 1
    robot.xy = (0.8, 0.8)  # 1.13 m from where the child last succeeded
    tick(root)
    assert len(plans(log)) == 2
    robot.xy = (1.2, 0.8)
    tick(root)
    assert len(plans(log)) == 2  # 0.4 m from the new start
    assert robot.frames[0] == ("map", "")
    robot.xy = None
    assert tick(root) == Status.FAILURE
    assert node.feedback_message == "robot pose not available"


def test_speed_controller_rate_follows_the_speed() -> None:
    log, clock = Log(), Clock()
    speed = {"v": 0.0}
    variables = DictVariables(goal="A")
    node = SpeedController("S", Scripted("Plan", ["SUCCESS"] * 20, log), lambda: speed["v"],
                           variables, clock=clock, min_rate=0.1, max_rate=1.0,
                           min_speed=0.0, max_speed=0.5)
    assert [node.rate(v) for v in (0.0, 0.25, 0.5, 2.0)] == pytest.approx([0.1, 0.55, 1.0, 1.0])
    root = pipeline(node, log)
    tick(root)
    assert len(plans(log)) == 1  # the first tick; period 1 / max_rate = 1 s
    clock.now = 0.5
    tick(root)
    assert len(plans(log)) == 1
    clock.now = 1.0  # a period passed: ticked, the period becomes 1 / 0.1 = 10 s (speed 0)
    tick(root)
    assert len(plans(log)) == 2 and node.period == pytest.approx(10.0)
    clock.now = 5.0
    tick(root)
    assert len(plans(log)) == 2
    variables["goal"] = "B"  # a new goal ticks the child at once
    tick(root)
    assert len(plans(log)) == 3
    speed["v"] = 0.5
    clock.now = 11.0
    tick(root)
    assert len(plans(log)) == 4 and node.period == pytest.approx(1.0)



def test_speed_controller_new_goal_restarts_the_period_at_max_rate() -> None:
    # Nav2 Jazzy: a new goal sets period_ = 1 / max_rate and start_ = now (not only
    # first_tick_), so the child is ticked again one max-rate period after the new goal.
    log, clock = Log(), Clock()
    variables = DictVariables(goal="A")
    node = SpeedController("S", Scripted("Plan", ["SUCCESS"] * 20, log), lambda: 0.0,
                           variables, clock=clock, min_rate=0.1, max_rate=1.0)
    root = pipeline(node, log)
    tick(root)
    clock.now = 1.0  # period passed at speed 0: the period becomes 10 s
    tick(root)
    assert len(plans(log)) == 2 and node.period == pytest.approx(10.0)
    clock.now = 5.0
    variables["goal"] = "B"
    tick(root)
    assert len(plans(log)) == 3 and node.period == pytest.approx(1.0)
    clock.now = 5.5
    tick(root)
    assert len(plans(log)) == 3
    clock.now = 6.0  # one max-rate period after the new goal
    tick(root)
    assert len(plans(log)) == 4

def pose(stamp: float) -> SimpleNamespace:
    ns = SimpleNamespace
    return ns(header=ns(stamp=ns(sec=int(stamp), nanosec=int((stamp % 1) * 1e9))), name=stamp)


def test_goal_updater_takes_a_newer_goal_only() -> None:
    log = Log()
    received: dict[str, object] = {"goal": None}
    variables = DictVariables(goal=pose(10.0))
    node = GoalUpdater("U", Scripted("Plan", ["SUCCESS"] * 5, log), lambda: received["goal"],
                       variables, input_goal="goal", output_goal="updated")
    assert tick(node) == Status.SUCCESS
    assert variables["updated"].name == 10.0  # no update: the input goal
    received["goal"] = pose(5.0)  # older: ignored
    tick(node)
    assert variables["updated"].name == 10.0
    assert node.feedback_message == "the received goal is older than the current one"
    received["goal"] = pose(0.0)  # no stamp: ignored
    tick(node)
    assert variables["updated"].name == 10.0
    received["goal"] = pose(12.5)
    tick(node)
    assert variables["updated"].name == 12.5
    assert len(log.visits) == 4  # the child is ticked every time


def test_they_load_from_a_tree_file_with_the_context(tmp_path: Path, registry: Registry) -> None:
    tree = tmp_path / "robot.yaml"
    tree.write_text("format: 1\nblackboard:\n  goal: {type: geometry_msgs/msg/PoseStamped}\n"
                    "  updated: {type: geometry_msgs/msg/PoseStamped}\n"
                    "root:\n  DistanceController:\n    distance: 2.0\n    child:\n"
                    "      SpeedController:\n        max_rate: 2.0\n        child:\n"
                    "          GoalUpdater:\n            input_goal: '{goal}'\n"
                    "            output_goal: '{updated}'\n"
                    "            child: {Fixed: {status: success}}\n")
    Blackboard.storage.clear()
    Blackboard.storage["/goal"] = pose(1.0)
    robot = Robot()
    context = {ROBOT_POSE_KEY: robot, ROBOT_SPEED_KEY: lambda: 0.2,
               GOAL_UPDATE_KEY: lambda: pose(2.0), CLOCK_KEY: Clock()}
    root = load_tree(tree, context, registry=registry).root
    assert isinstance(root, DistanceController) and root.distance == 2.0
    assert robot.started == 1  # the source was started when the node was built
    root.tick_once()
    assert root.status == Status.SUCCESS
    assert Blackboard.storage["/updated"].name == 2.0
    assert load_tree(tree, {}, registry=registry).root.pose("map", "base") is None  # no source
