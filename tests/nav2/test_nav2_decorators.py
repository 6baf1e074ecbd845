"""Nav2's GoalUpdatedController and PathLongerOnApproach, ticked in py_trees (no ROS).

Behaviour read from ``nav2_behavior_tree`` (``goal_updated_controller.cpp``,
``path_longer_on_approach.cpp``); messages are stood in for by objects with the same
fields (the engine reads fields by name and never imports a message type).
"""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

from engine.script_variables import DictVariables
from engine.scripted_leaves import Log, Scripted, tick
from py_trees.blackboard import Blackboard
from py_trees.common import Status
from sar_plugins.nav2.controls import PipelineSequence
from sar_plugins.nav2.decorators import (
    GoalUpdatedController,
    PathLongerOnApproach,
    path_length,
)

from sar_framework.engine.api import load_tree
from sar_framework.engine.registry import Registry


def path(*points: tuple[float, float]) -> SimpleNamespace:
    ns = SimpleNamespace
    return ns(poses=[ns(pose=ns(position=ns(x=x, y=y, z=0.0))) for x, y in points])


def test_goal_updated_controller_ticks_the_child_on_start_change_and_while_running() -> None:
    """As in Nav2's trees: under a PipelineSequence, beside a running FollowPath."""
    log = Log()
    variables = DictVariables(goal="A")
    plan = Scripted("Plan", ["RUNNING", "SUCCESS", "SUCCESS", "SUCCESS"], log)
    node = PipelineSequence("P", [
        GoalUpdatedController("G", plan, "goal", "goals", variables),
        Scripted("Follow", ["RUNNING"] * 10, log)])
    assert tick(node) == Status.RUNNING  # starting counts as a change: Plan runs
    assert tick(node) == Status.RUNNING  # Plan is running: ticked again, succeeds
    assert log.visits == ["Plan RUNNING", "Plan SUCCESS", "Follow RUNNING"]
    log.visits.clear()
    assert tick(node) == Status.RUNNING  # no change, Plan done: not ticked (RUNNING)
    assert log.visits == ["Follow RUNNING"]  # (the pipeline goes on past a RUNNING child)
    variables["goal"] = "B"
    tick(node)
    assert log.visits[1:] == ["Plan SUCCESS", "Follow RUNNING"]
    variables["goals"] = ["B", "C"]  # the list counts too
    tick(node)
    assert log.visits[3:] == ["Plan SUCCESS", "Follow RUNNING"]


def test_path_longer_on_approach_only_for_a_much_longer_path_to_the_same_goal() -> None:
    log = Log()
    variables = DictVariables(path=path((0, 0), (0.5, 0), (1, 0)))  # 1 m
    node = PathLongerOnApproach("P", Scripted("Wait", ["RUNNING", "SUCCESS", "SUCCESS"], log),
                                "path", variables, prox_len=3.0, length_factor=2.0)
    assert tick(node) == Status.SUCCESS  # first path: remembered
    variables["path"] = path((0, 0), (0, 1), (1, 1), (1, 0))  # 3 m to the same goal
    assert tick(node) == Status.RUNNING
    assert tick(node) == Status.SUCCESS  # the child completed: the new path is the old one
    assert log.visits == ["Wait RUNNING", "Wait SUCCESS"]
    assert tick(node) == Status.SUCCESS and len(log.visits) == 2  # same path: not ticked
    variables["path"] = path((1, 0), (5, 0))  # another goal: a first path again
    assert tick(node) == Status.SUCCESS
    variables["path"] = path((1, 0), (3, 0), (5, 0))  # not longer
    assert tick(node) == Status.SUCCESS and len(log.visits) == 2
    assert path_length(path((0, 0), (3, 4))) == 5.0


def test_path_longer_on_approach_far_from_the_goal_does_nothing() -> None:
    log = Log()
    variables = DictVariables(path=path((0, 0), (4, 0)))  # 4 m: not near (prox_len 3)
    node = PathLongerOnApproach("P", Scripted("Wait", ["SUCCESS"], log), "path", variables)
    tick(node)
    variables["path"] = path((0, 0), (0, 5), (4, 5), (4, 0))
    assert tick(node) == Status.SUCCESS and log.visits == []


def test_both_load_from_a_tree_file_on_the_blackboard(tmp_path: Path,
                                                      registry: Registry) -> None:
    tree = tmp_path / "goal.yaml"
    tree.write_text("format: 1\nblackboard:\n  path: {type: nav_msgs/msg/Path}\n"
                    "root:\n  GoalUpdatedController:\n    child:\n"
                    "      PathLongerOnApproach:\n        path: '{path}'\n        prox_len: 1.5\n"
                    "        child: {Fixed: {status: running}}\n")
    Blackboard.storage.clear()
    Blackboard.storage["/goal"] = "A"
    root = load_tree(tree, {}, registry=registry).root
    inner = root.decorated
    assert isinstance(root, GoalUpdatedController) and root.names == ("goal", "goals")
    assert isinstance(inner, PathLongerOnApproach) and inner.prox_len == 1.5
    root.tick_once()
    assert root.status == Status.SUCCESS  # no path yet: PathLongerOnApproach succeeds
