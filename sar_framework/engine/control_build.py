"""Build the behaviours of BT.CPP's and Nav2's node kinds (:mod:`.control_kinds`).

One builder per kind, called as ``builder(node, children, context)``; the clock-driven
ones read the build context's ``clock`` (:data:`.clock_timeout.CLOCK_KEY`, a callable
returning seconds; default ``time.monotonic``). The blackboard nodes get a
:class:`~.variables.Variables` over py_trees' blackboard: a variable ``name`` (written
``"{name}"``, ``"{@name}"`` or ``name``) is the entry ``/name`` of the main tree's scope.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping
from typing import Any

import py_trees

from sar_framework.engine.clock_timeout import CLOCK_KEY
from sar_framework.engine.control_kinds import CONTROL_KINDS, SWITCH_CASES
from sar_framework.engine.controls import (
    conditionals,
    converters,
    leaves,
    loops,
    nav2_controls,
    nav2_decorators,
    nav2_robot,
    parallels,
    queues,
    sequences,
    timing,
    updated,
)
from sar_framework.engine.controls.values import DictVariables
from sar_framework.engine.robot_context import pose_source, speed_source, update_source
from sar_framework.engine.spec import Category, NodeSpec
from sar_framework.engine.variables import BlackboardVariables, Variables

Behaviour = py_trees.behaviour.Behaviour
ControlBuilder = Callable[[NodeSpec, list[Behaviour], Mapping[str, Any]], Behaviour]


def variable_name(text: str) -> str:
    """The variable a port text names: ``{goal}``, ``{@goal}`` and ``goal`` all name goal."""
    text = text.strip()
    if len(text) > 2 and text[0] == "{" and text[-1] == "}":
        text = text[1:-1]
    return text.lstrip("@")


def is_entry(text: str) -> bool:
    """Whether a port text names an entry (``{name}``) rather than being a literal."""
    text = text.strip()
    return len(text) > 2 and text[0] == "{" and text[-1] == "}"


def blackboard_variables(node: NodeSpec, names: list[str], writable: list[str] = ()
                         ) -> Variables:  # type: ignore[assignment]
    """A view of py_trees' blackboard for ``node``: each name is the entry ``/name``."""
    return BlackboardVariables(node.name, {name: "/" + name for name in names}, writable)


def _clock(context: Mapping[str, Any]) -> Callable[[], float]:
    clock = context.get(CLOCK_KEY)
    return clock if callable(clock) else time.monotonic


def _plain(cls: type) -> ControlBuilder:
    """A control or decorator whose attributes (other than name) are its keyword args."""

    def build(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
              ) -> Behaviour:
        if node.category is Category.DECORATOR:
            return cls(node.name, children[0], **node.attrs)
        if node.category is Category.COMPOSITE:
            return cls(node.name, children, **node.attrs)
        return cls(node.name, **node.attrs)

    return build


def _clocked(cls: type) -> ControlBuilder:
    """A decorator or leaf that also takes the build context's clock."""

    def build(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
              ) -> Behaviour:
        head = [children[0]] if children else []
        return cls(node.name, *head, **node.attrs, clock=_clock(context))

    return build


def _switch(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
            ) -> Behaviour:
    cases = [node.attrs[f"case_{i}"] for i in range(1, SWITCH_CASES[node.kind] + 1)]
    text = node.attrs["variable"]
    if is_entry(text):
        name = variable_name(text)
        variables = blackboard_variables(node, [name])
    else:
        name, variables = "variable", DictVariables({"variable": text})
    return conditionals.Switch(node.name, children, cases, name, variables)


def _updated(cls: type) -> ControlBuilder:
    def build(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
              ) -> Behaviour:
        name = variable_name(node.attrs["entry"])
        return cls(node.name, children[0], name, blackboard_variables(node, [name]))

    return build


def _loop(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
          ) -> Behaviour:
    text, value = node.attrs["queue"], node.attrs.get("value")
    shared = variable_name(text) if is_entry(text) else None
    output = variable_name(value) if value else None
    names = [name for name in (shared, output) if name is not None]
    variables = blackboard_variables(node, names, [output] if output else [])
    return queues.Loop(node.name, children[0], None if shared else text, variables,
                       item=queues.ITEM_TYPES[node.kind], queue_variable=shared,
                       value=output, if_empty=node.attrs["if_empty"])


def _was_updated(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
                 ) -> Behaviour:
    name = variable_name(node.attrs["entry"])
    return updated.WasEntryUpdated(node.name, name, blackboard_variables(node, [name]))


def _goal_updated(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
                  ) -> Behaviour:
    goal, goals = variable_name(node.attrs["goal"]), variable_name(node.attrs["goals"])
    return nav2_decorators.GoalUpdatedController(
        node.name, children[0], goal, goals, blackboard_variables(node, [goal, goals]))


def _path_longer(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
                 ) -> Behaviour:
    path = variable_name(node.attrs["path"])
    return nav2_decorators.PathLongerOnApproach(
        node.name, children[0], path, blackboard_variables(node, [path]),
        prox_len=node.attrs["prox_len"], length_factor=node.attrs["length_factor"])


def _distance(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
              ) -> Behaviour:
    return nav2_robot.DistanceController(node.name, children[0], pose_source(context),
                                         **node.attrs)


def _speed(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
           ) -> Behaviour:
    attrs = dict(node.attrs)
    goal, goals = variable_name(attrs.pop("goal")), variable_name(attrs.pop("goals"))
    return nav2_robot.SpeedController(
        node.name, children[0], speed_source(context), blackboard_variables(node, [goal, goals]),
        goal=goal, goals=goals, clock=_clock(context), **attrs)


def _goal_updater(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
                  ) -> Behaviour:
    read = variable_name(node.attrs["input_goal"])
    write = variable_name(node.attrs["output_goal"])
    return nav2_robot.GoalUpdater(
        node.name, children[0], update_source(context),
        blackboard_variables(node, [read, write], [write]), input_goal=read, output_goal=write)


def _set_blackboard(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
                    ) -> Behaviour:
    value, output = node.attrs["value"], variable_name(node.attrs["output_key"])
    names = [output] + ([variable_name(value)] if is_entry(value) else [])
    variables = blackboard_variables(node, names, [output])
    return leaves.SetBlackboard(node.name, value, output, variables)


def _unset_blackboard(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
                      ) -> Behaviour:
    key = variable_name(node.attrs["key"])
    return leaves.UnsetBlackboard(node.name, key, blackboard_variables(node, [key], [key]))


CONTROL_BUILDERS: dict[str, ControlBuilder] = {
    "Sequence": _plain(sequences.Sequence),
    "SequenceWithMemory": _plain(sequences.SequenceWithMemory),
    "ReactiveSequence": _plain(sequences.ReactiveSequence),
    "AsyncSequence": _plain(sequences.AsyncSequence),
    "AsyncFallback": _plain(sequences.AsyncFallback),
    "Fallback": _plain(sequences.Fallback),
    "ReactiveFallback": _plain(sequences.ReactiveFallback),
    "Parallel": _plain(parallels.Parallel),
    "ParallelAll": _plain(parallels.ParallelAll),
    "IfThenElse": _plain(conditionals.IfThenElse),
    "WhileDoElse": _plain(conditionals.WhileDoElse),
    **{key: _switch for key in SWITCH_CASES},
    "RecoveryNode": _plain(nav2_controls.RecoveryNode),
    "PipelineSequence": _plain(nav2_controls.PipelineSequence),
    "RoundRobin": _plain(nav2_controls.RoundRobin),
    "Inverter": _plain(converters.Inverter),
    "ForceSuccess": _plain(converters.ForceSuccess),
    "ForceFailure": _plain(converters.ForceFailure),
    "KeepRunningUntilFailure": _plain(converters.KeepRunningUntilFailure),
    "Repeat": _plain(loops.Repeat),
    "RetryUntilSuccessful": _plain(loops.RetryUntilSuccessful),
    "RunOnce": _plain(loops.RunOnce),
    "Delay": _clocked(timing.Delay),
    "Timeout": _clocked(timing.Timeout),
    **{key: _loop for key in queues.ITEM_TYPES},
    "WasEntryUpdated": _was_updated,
    "SkipUnlessUpdated": _updated(updated.SkipUnlessUpdated),
    "WaitValueUpdate": _updated(updated.WaitValueUpdate),
    "RateController": _clocked(nav2_decorators.RateController),
    "SingleTrigger": _plain(nav2_decorators.SingleTrigger),
    "GoalUpdatedController": _goal_updated,
    "PathLongerOnApproach": _path_longer,
    "DistanceController": _distance,
    "SpeedController": _speed,
    "GoalUpdater": _goal_updater,
    "AlwaysSuccess": _plain(leaves.AlwaysSuccess),
    "AlwaysFailure": _plain(leaves.AlwaysFailure),
    "Sleep": _clocked(leaves.Sleep),
    "SetBlackboard": _set_blackboard,
    "UnsetBlackboard": _unset_blackboard,
}
assert set(CONTROL_BUILDERS) == {k.key for k in CONTROL_KINDS}, "a kind without a builder"
