"""Script, ScriptCondition, Precondition and PrePostConditions, tick by tick.

Cases marked "BT.CPP" restate BehaviorTree.CPP 4.7.3's tests (gtest_preconditions.cpp,
gtest_postconditions.cpp) with py_trees composites standing in for BT.CPP's. SKIPPED is
SUCCESS plus the skipped mark (engine/nodes/skipping.py).
"""

from __future__ import annotations

import py_trees
import pytest
from py_trees.behaviour import Behaviour
from py_trees.common import Status

from sar_framework.engine.nodes.script_nodes import (
    ATTRIBUTES,
    ElseStatus,
    Precondition,
    PrePostConditions,
    Script,
    ScriptCondition,
)
from sar_framework.engine.nodes.skipping import was_skipped
from sar_framework.engine.scripting import ScriptError, compile_script

from ..script_variables import DictVariables

S = compile_script


class Leaf(Behaviour):
    """Returns its statuses in turn (the last one repeats); counts ticks and halts."""

    def __init__(self, name: str, *statuses: Status) -> None:
        super().__init__(name=name)
        self.statuses = list(statuses) or [Status.SUCCESS]
        self.ticks = 0
        self.halts = 0

    def update(self) -> Status:
        status = self.statuses[min(self.ticks, len(self.statuses) - 1)]
        self.ticks += 1
        return status

    def terminate(self, new_status: Status) -> None:
        if new_status == Status.INVALID and self.status == Status.RUNNING:
            self.halts += 1


def tick(root: Behaviour) -> Status:
    root.tick_once()
    return root.status


def sequence(*children: Behaviour) -> py_trees.composites.Sequence:
    return py_trees.composites.Sequence("seq", memory=True, children=list(children))


# --- Script and ScriptCondition -------------------------------------------------------------

def test_script_runs_its_code_and_succeeds() -> None:
    v = DictVariables(count=1)
    node = Script("inc", S("count += 1; count > 100"), v)
    assert tick(node) == Status.SUCCESS  # the value (false) does not matter
    assert tick(node) == Status.SUCCESS
    assert v["count"] == 3
    assert not was_skipped(node)


def test_script_errors_are_raised_out_of_the_tick() -> None:
    node = Script("bad", S("missing + 1"), DictVariables())
    with pytest.raises(ScriptError, match="'missing' has no value"):
        node.tick_once()


@pytest.mark.parametrize(("code", "status"), [
    ("a > 1", Status.SUCCESS), ("a < 1", Status.FAILURE), ("true", Status.SUCCESS),
    ("0", Status.FAILURE), ("1", Status.SUCCESS), ("0.5", Status.SUCCESS),
    ("b := a * 2; b == 4", Status.SUCCESS),
])
def test_script_condition(code: str, status: Status) -> None:
    v = DictVariables(a=2)
    node = ScriptCondition("cond", S(code), v)
    assert tick(node) == status
    assert not was_skipped(node)


@pytest.mark.parametrize(("code", "message"), [
    ("2", "2 is not a boolean"), ("'yes'", "str 'yes' is not a boolean"),
    ("a := 1; 'x' .. a", "str 'x1' is not a boolean"),
])
def test_a_condition_that_is_not_a_boolean_is_an_error(code: str, message: str) -> None:
    node = ScriptCondition("cond", S(code), DictVariables())
    with pytest.raises(ScriptError, match=message):
        node.tick_once()


# --- Precondition ---------------------------------------------------------------------------

def test_precondition_integers_bt_cpp() -> None:
    # BT.CPP: PreconditionsDecorator.Integers (and DoubleEquals, StringEquals below)
    v = DictVariables()
    a, b, c = Leaf("TestA"), Leaf("TestB"), Leaf("TestC")
    root = sequence(
        Script("init", S("A:=1; B:=1; C:=3"), v),
        Precondition("p1", a, S("A==B"), v, ElseStatus.FAILURE),
        Precondition("p2", b, S("A==C"), v, ElseStatus.SUCCESS),
        Precondition("p3", c, S("A!=C"), v, ElseStatus.FAILURE))
    assert tick(root) == Status.SUCCESS
    assert (a.ticks, b.ticks, c.ticks) == (1, 0, 1)


@pytest.mark.parametrize("init", ["A:=1.1; B:=(1.0+0.1); C:= 2.0", "A:='x'; B:='x'; C:='y'"])
def test_precondition_doubles_and_strings_bt_cpp(init: str) -> None:
    v = DictVariables()
    a, b, c = Leaf("TestA"), Leaf("TestB"), Leaf("TestC")
    root = sequence(
        Script("init", S(init), v),
        Precondition("p1", a, S("A==B"), v),
        Precondition("p2", b, S("A==C"), v, ElseStatus.SUCCESS),
        Precondition("p3", c, S("A!=C"), v))
    assert tick(root) == Status.SUCCESS
    assert (a.ticks, b.ticks, c.ticks) == (1, 0, 1)


@pytest.mark.parametrize(("otherwise", "status", "skipped"), [
    (ElseStatus.FAILURE, Status.FAILURE, False), (ElseStatus.SUCCESS, Status.SUCCESS, False),
    (ElseStatus.RUNNING, Status.RUNNING, False), (ElseStatus.SKIPPED, Status.SUCCESS, True),
])
def test_precondition_else(otherwise: ElseStatus, status: Status, skipped: bool) -> None:
    v = DictVariables(go=False)
    child = Leaf("child")
    node = Precondition("p", child, S("go"), v, otherwise)
    assert tick(node) == status
    assert was_skipped(node) is skipped
    assert child.ticks == 0
    v["go"] = True
    assert tick(node) == Status.SUCCESS
    assert not was_skipped(node)
    assert child.ticks == 1


def test_precondition_else_running_evaluates_the_condition_every_tick() -> None:
    v = DictVariables(go=False)
    child = Leaf("child")
    node = Precondition("p", child, S("go"), v, ElseStatus.RUNNING)
    assert [tick(node), tick(node)] == [Status.RUNNING, Status.RUNNING]
    v["go"] = True
    assert tick(node) == Status.SUCCESS
    assert child.ticks == 1


def test_precondition_checks_the_condition_once_bt_cpp() -> None:
    # BT.CPP: PreconditionsDecorator.ChecksConditionOnce
    v = DictVariables()
    keep = Leaf("KeepRunning", Status.RUNNING)
    root = sequence(
        Script("a", S("A:=0"), v), Script("b", S("B:=0"), v),
        Precondition("p", PrePostConditions("kr", keep, v, while_=S("B==0")), S("A==0"), v))
    assert tick(root) == Status.RUNNING
    v["A"] = 1  # while the child runs, the condition is not evaluated again
    assert tick(root) == Status.RUNNING
    v["B"] = 1  # _while halts the child: SKIPPED, which the sequence passes over
    assert tick(root) == Status.SUCCESS
    assert keep.halts == 1


def test_precondition_can_run_its_child_many_times_bt_cpp() -> None:
    # BT.CPP: PreconditionsDecorator.CanRunChildrenMultipleTimes. py_trees' Repeat starts
    # the next round on the next tick (BT.CPP's in the same tick), hence the extra ticks.
    v = DictVariables(A=0, B=0, C=1)
    test_a = Leaf("TestA")
    body = sequence(
        Precondition("p", test_a, S(" A==0 "), v, ElseStatus.SUCCESS),
        PrePostConditions("k1", Leaf("KeepRunning1", Status.RUNNING), v, while_=S("C==0")),
        PrePostConditions("k2", Leaf("KeepRunning2", Status.RUNNING), v, while_=S("B==0")))
    root = py_trees.decorators.Repeat("repeat", body, num_success=3)
    assert tick(root) == Status.RUNNING
    assert test_a.ticks == 1
    v.update(A=1, B=1, C=0)
    assert [tick(root), tick(root)] == [Status.RUNNING, Status.RUNNING]
    assert test_a.ticks == 1  # the second round's precondition is false
    v.update(A=0, C=1)
    assert [tick(root), tick(root)] == [Status.RUNNING, Status.SUCCESS]
    assert test_a.ticks == 2


def test_precondition_evaluates_again_once_the_child_has_finished() -> None:
    v = DictVariables(go=True)
    child = Leaf("child", Status.RUNNING, Status.SUCCESS)
    node = Precondition("p", child, S("go"), v)
    assert tick(node) == Status.RUNNING
    v["go"] = False
    assert tick(node) == Status.SUCCESS  # running: not evaluated again
    assert tick(node) == Status.FAILURE  # finished: evaluated, false
    assert child.ticks == 2


def test_precondition_passes_on_a_skipped_child() -> None:
    v = DictVariables(skip=True)
    child = Leaf("child")
    node = Precondition("p", PrePostConditions("w", child, v, skip_if=S("skip")), S("1"), v)
    assert tick(node) == Status.SUCCESS
    assert was_skipped(node)
    assert child.ticks == 0


def test_a_halted_precondition_evaluates_its_condition_again() -> None:
    v = DictVariables(go=True)
    child = Leaf("child", Status.RUNNING)
    node = Precondition("p", child, S("go"), v)
    assert tick(node) == Status.RUNNING
    node.stop(Status.INVALID)
    assert child.halts == 1
    v["go"] = False
    assert tick(node) == Status.FAILURE
    assert child.ticks == 1


# --- PrePostConditions: pre-conditions -------------------------------------------------------

def test_attribute_names() -> None:
    assert list(ATTRIBUTES) == ["_failureIf", "_successIf", "_skipIf", "_while", "_onSuccess",
                                "_onFailure", "_onHalted", "_post"]
    child, v = Leaf("c"), DictVariables()
    node = PrePostConditions("n", child, v, **{ATTRIBUTES["_skipIf"]: S("1")})
    assert tick(node) == Status.SUCCESS and was_skipped(node)


def test_success_if_and_failure_if_bt_cpp() -> None:
    # BT.CPP: Preconditions.Basic
    v = DictVariables()
    a, b, c, d = Leaf("TestA"), Leaf("TestB"), Leaf("TestC"), Leaf("TestD")
    root = sequence(
        Script("init", S("A:=1"), v),
        PrePostConditions("a", a, v, success_if=S("A==1")),
        PrePostConditions("b", b, v, success_if=S("A==2")),
        py_trees.composites.Selector("fallback", memory=True, children=[
            PrePostConditions("c", c, v, failure_if=S("A==1")),
            PrePostConditions("d", d, v, failure_if=S("A!=1"))]))
    assert tick(root) == Status.SUCCESS
    assert (a.ticks, b.ticks, c.ticks, d.ticks) == (0, 1, 0, 1)


def test_skip_if_with_on_success_bt_cpp() -> None:
    # BT.CPP: Preconditions.Issue533
    v = DictVariables(A=3)
    a, b, c = Leaf("TestA"), Leaf("TestB"), Leaf("TestC")
    root = sequence(
        PrePostConditions("a", a, v, skip_if=S("A!=1")),
        PrePostConditions("b", b, v, skip_if=S("A!=2"), on_success=S("A=1")),
        PrePostConditions("c", c, v, skip_if=S("A!=3"), on_success=S("A=2")))
    tick(root)
    assert (a.ticks, b.ticks, c.ticks) == (0, 0, 1)
    tick(root)
    assert (a.ticks, b.ticks, c.ticks) == (0, 1, 1)
    tick(root)
    assert (a.ticks, b.ticks, c.ticks) == (1, 1, 1)


def test_a_skipped_node_is_never_ticked_bt_cpp() -> None:
    # BT.CPP: Preconditions.Issue585 and SkippedSequence
    v = DictVariables(skip=True)
    child = Leaf("child")
    node = PrePostConditions("n", child, v, skip_if=S("skip"))
    for skip in (True, False, True, False):
        v["skip"] = skip
        assert tick(node) == Status.SUCCESS
        assert was_skipped(node) is skip
    assert child.ticks == 2


def test_skip_if_is_not_evaluated_while_running_bt_cpp() -> None:
    # BT.CPP: Preconditions.Issue615_NoSkipWhenRunning_B
    v = DictVariables(check=False)
    keep = Leaf("KeepRunning", Status.RUNNING)
    node = PrePostConditions("n", keep, v, skip_if=S("check==false"))
    assert tick(node) == Status.SUCCESS and was_skipped(node)
    v["check"] = True
    assert tick(node) == Status.RUNNING and not was_skipped(node)
    v["check"] = False
    assert tick(node) == Status.RUNNING
    assert keep.ticks == 2


def test_skipping_in_a_sequence_bt_cpp() -> None:
    # BT.CPP: SkippingLogic.Sequence and SkippingLogic.WhileSkip
    v = DictVariables()
    a, b = Leaf("TestA"), Leaf("TestB")
    root = sequence(Script("init", S("A:=1"), v),
                    PrePostConditions("a", a, v, success_if=S("A==2"), failure_if=S("A!=1"),
                                      skip_if=S("A==1")),
                    b)
    assert tick(root) == Status.SUCCESS
    assert (a.ticks, b.ticks) == (0, 1)
    for doit, ticks in (("true", 1), ("false", 0)):
        leaf = Leaf("Test")
        root = sequence(Script("init", S(f" doit:={doit} "), v),
                        sequence(PrePostConditions("t", leaf, v, while_=S("doit"))))
        assert tick(root) == Status.SUCCESS
        assert leaf.ticks == ticks


def test_the_order_is_failure_success_skip_while() -> None:
    v = DictVariables(f=True, s=True, k=True, w=False)
    child = Leaf("child")
    node = PrePostConditions("n", child, v, failure_if=S("f"), success_if=S("s"),
                             skip_if=S("k"), while_=S("w"))
    expected = [(Status.FAILURE, False, "f"), (Status.SUCCESS, False, "s"),
                (Status.SUCCESS, True, "k"), (Status.SUCCESS, True, None)]
    for status, skipped, clear in expected:
        assert (tick(node), was_skipped(node)) == (status, skipped)
        if clear:
            v[clear] = False
    v["w"] = True
    assert (tick(node), was_skipped(node)) == (Status.SUCCESS, False)
    assert child.ticks == 1


def test_while_false_before_the_start_skips_without_on_halted() -> None:
    v = DictVariables(ok=False, halted=0)
    child = Leaf("child", Status.RUNNING)
    node = PrePostConditions("n", child, v, while_=S("ok"), on_halted=S("halted += 1"))
    assert tick(node) == Status.SUCCESS and was_skipped(node)
    assert (child.ticks, v["halted"]) == (0, 0)


def test_while_false_while_running_halts_and_runs_on_halted_bt_cpp() -> None:
    # BT.CPP: Preconditions.WhileCallsOnHalt
    v = DictVariables(A=1, B=0)
    keep = Leaf("KeepRunning", Status.RUNNING)
    root = sequence(PrePostConditions("n", keep, v, while_=S("A==1"), on_halted=S("B=69"),
                                      post=S("B=1")))
    assert tick(root) == Status.RUNNING
    assert v["B"] == 0
    assert tick(root) == Status.RUNNING  # _while is evaluated every tick while running
    v["A"] = 0
    node = root.children[0]
    assert tick(root) == Status.SUCCESS
    assert was_skipped(node)
    assert v["B"] == 69  # _post does not run after a halt
    assert (keep.ticks, keep.halts, keep.status) == (2, 1, Status.INVALID)
    v["A"] = 1  # it starts again from scratch
    assert tick(root) == Status.RUNNING
    assert keep.ticks == 3


# --- PrePostConditions: post-conditions ------------------------------------------------------

def test_on_success_and_on_failure_bt_cpp() -> None:
    # BT.CPP: PostConditions.BasicTest (a _failureIf's FAILURE runs _onFailure too)
    v = DictVariables()
    root = sequence(
        Script("init", S("A:=1; B:=1; C:=1; D:=1"), v),
        PrePostConditions("s", Leaf("AlwaysSuccess"), v, on_success=S("B=42")),
        py_trees.decorators.FailureIsSuccess("fs1", PrePostConditions(
            "f1", Leaf("AlwaysSuccess"), v, failure_if=S("A!=0"), on_failure=S("C=42"))),
        py_trees.decorators.FailureIsSuccess("fs2", PrePostConditions(
            "f2", Leaf("AlwaysFailure", Status.FAILURE), v, on_failure=S("D=42"))))
    assert tick(root) == Status.SUCCESS
    assert (v["B"], v["C"], v["D"]) == (42, 42, 42)


def test_on_failure_and_post_on_every_retry_bt_cpp() -> None:
    # BT.CPP: PostConditions.Issue539
    v = DictVariables()
    root = sequence(
        Script("init", S("x:=0; y:=0"), v),
        py_trees.decorators.Retry("retry", PrePostConditions(
            "f", Leaf("AlwaysFailure", Status.FAILURE), v,
            on_failure=S("x  += 1"), post=S("y  += 1")), num_failures=5))
    status = tick(root)
    while status == Status.RUNNING:
        status = tick(root)
    assert status == Status.FAILURE
    assert (v["x"], v["y"]) == (5, 5)


def test_on_halted_when_a_parallel_halts_it_bt_cpp() -> None:
    # BT.CPP: PostConditions.Issue601
    v = DictVariables()
    sleep = Leaf("Sleep", Status.RUNNING)
    root = sequence(
        Script("init", S("test := 'start'"), v),
        py_trees.composites.Parallel("parallel", py_trees.common.ParallelPolicy.SuccessOnAll(),
                                     children=[
            PrePostConditions("sleep", sleep, v, on_halted=S("test = 'halted'"),
                              post=S("test = 'post'")),
            Leaf("AlwaysFailure", Status.FAILURE)]))
    assert tick(root) == Status.FAILURE
    assert v["test"] == "halted"
    assert sleep.halts == 1


def test_on_halted_when_a_higher_priority_takes_over() -> None:
    v = DictVariables(urgent=False, log="")
    worker = Leaf("worker", Status.RUNNING)
    root = py_trees.composites.Selector("priorities", memory=False, children=[
        ScriptCondition("urgent?", S("urgent"), v),
        PrePostConditions("work", worker, v, on_halted=S("log = log .. 'halted;'"),
                          on_success=S("log = log .. 'success;'"))])
    assert tick(root) == Status.RUNNING
    v["urgent"] = True
    assert tick(root) == Status.SUCCESS
    assert v["log"] == "halted;"
    assert worker.halts == 1


def test_on_halted_does_not_run_unless_the_node_was_running() -> None:
    v = DictVariables(n=0)
    node = PrePostConditions("n", Leaf("done"), v, on_halted=S("n += 1"))
    assert tick(node) == Status.SUCCESS
    node.stop(Status.INVALID)
    assert v["n"] == 0


def test_post_conditions_run_once_when_the_node_finishes() -> None:
    v = DictVariables(log="")
    child = Leaf("child", Status.RUNNING, Status.RUNNING, Status.FAILURE)
    node = PrePostConditions("n", child, v, on_success=S("log = log .. 's'"),
                             on_failure=S("log = log .. 'f'"), post=S("log = log .. 'p'"))
    assert [tick(node), tick(node)] == [Status.RUNNING, Status.RUNNING]
    assert v["log"] == ""
    assert tick(node) == Status.FAILURE
    assert v["log"] == "fp"


def test_no_post_conditions_after_skipped() -> None:
    v = DictVariables(log="")
    node = PrePostConditions("n", Leaf("c"), v, skip_if=S("1"), on_success=S("log = 's'"),
                             post=S("log = 'p'"))
    assert tick(node) == Status.SUCCESS and was_skipped(node)
    assert v["log"] == ""


def test_a_skipped_child_is_passed_on_without_post_conditions() -> None:
    v = DictVariables(log="")
    inner = PrePostConditions("inner", Leaf("c"), v, skip_if=S("1"))
    node = PrePostConditions("outer", inner, v, post=S("log = 'p'"))
    assert tick(node) == Status.SUCCESS and was_skipped(node)
    assert v["log"] == ""


def test_script_errors_in_conditions_are_raised() -> None:
    node = PrePostConditions("n", Leaf("c"), DictVariables(), skip_if=S("nothing"))
    with pytest.raises(ScriptError, match="'nothing' has no value"):
        node.tick_once()
    node = PrePostConditions("n", Leaf("c"), DictVariables(n=2), skip_if=S("n"))
    with pytest.raises(ScriptError, match="2 is not a boolean"):
        node.tick_once()
