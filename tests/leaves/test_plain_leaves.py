"""The toolkit's leaves without ROS: declared values, conditions, stateful moments."""

from __future__ import annotations

import py_trees
import pytest
from py_trees.common import Status

from sar_framework.engine.plugin import Param, leaf
from sar_framework.leaves import Condition, Leaf, StatefulLeaf
from sar_framework.testing import assert_statuses, leaf_run


@leaf(params=[Param("limit", int, default=2)])
class Pulses(StatefulLeaf):
    """Count to ``limit`` ticks, then succeed; remember halts."""

    halts = 0

    def on_start(self) -> Status:
        self.count = 1
        return Status.RUNNING

    def on_running(self) -> Status:
        self.count += 1
        return Status.SUCCESS if self.count >= self.limit else Status.RUNNING

    def on_halted(self) -> None:
        type(self).halts += 1


@leaf(params=[Param("threshold", int, default=0)], condition=True)
class Positive(Condition):
    """Whether ``threshold`` is above zero."""

    def check(self) -> bool:
        return self.threshold > 0


def test_declared_values_arrive_as_attributes() -> None:
    assert Positive(name="p", threshold=3).threshold == 3


def test_a_declared_name_may_not_hide_the_behaviours_own() -> None:
    class Odd(Leaf):
        def update(self) -> Status:
            return Status.SUCCESS

    with pytest.raises(TypeError, match="'status' would hide"):
        Odd(name="odd", status=1)
    with pytest.raises(TypeError, match="'update' would hide"):
        Odd(name="odd", update=1)


def test_a_condition_answers_in_the_tick() -> None:
    assert Positive(name="p", threshold=1).tick_once() is None
    for threshold, expected in ((1, Status.SUCCESS), (0, Status.FAILURE)):
        cond = Positive(name="p", threshold=threshold)
        cond.tick_once()
        assert cond.status == expected


def test_a_stateful_leaf_starts_runs_and_is_halted() -> None:
    run = leaf_run("Pulses", {"limit": 3}, plugin_paths=[__file__])
    run.tick(3)
    assert_statuses(run, ["RUNNING", "RUNNING", "SUCCESS"])
    run.shutdown()
    pulses = Pulses(name="p", limit=5)
    tree = py_trees.trees.BehaviourTree(pulses)
    tree.tick()
    assert pulses.status == Status.RUNNING
    pulses.stop(Status.INVALID)
    assert Pulses.halts == 1
    pulses.stop(Status.INVALID)  # not RUNNING any more: no second halt
    assert Pulses.halts == 1
