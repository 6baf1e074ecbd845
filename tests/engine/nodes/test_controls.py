"""BT.CPP's controls in py_trees: what the BT.CPP checker cannot show (no ROS, no C++).

Halting (a running child is halted, a finished one only reset), the blackboard nodes on
a dict-backed ``Variables`` and on py_trees' blackboard, Switch's comparison, the clock
of Delay, Timeout and Sleep, and the builder's errors. The tick-by-tick equality with
BehaviorTree.CPP itself is in ``tests/interop/test_btcpp_controls.py``.
"""

from __future__ import annotations

from pathlib import Path

import py_trees
import pytest
from py_trees.common import Status

from sar_framework.engine.api import load_tree
from sar_framework.engine.building.control_build import CLOCK_KEY
from sar_framework.engine.diagnostics import TreeLoadError
from sar_framework.engine.nodes.controls.base import bt_status
from sar_framework.engine.nodes.controls.conditionals import Switch, case_matches
from sar_framework.engine.nodes.controls.leaves import SetBlackboard, Sleep, UnsetBlackboard
from sar_framework.engine.nodes.controls.sequences import ReactiveSequence, Sequence
from sar_framework.engine.nodes.controls.values import DictVariables
from sar_framework.engine.nodes.decorators.loops import RunOnce
from sar_framework.engine.nodes.decorators.queues import Loop
from sar_framework.engine.nodes.decorators.timing import Delay, Timeout
from sar_framework.engine.nodes.decorators.updated import (
    SkipUnlessUpdated,
    WaitValueUpdate,
    WasEntryUpdated,
)
from sar_framework.engine.nodes.skipping import was_skipped
from sar_framework.engine.registry import Registry
from sar_framework.engine.variables import BlackboardVariables

from ..conftest import load_problems
from ..scripted_leaves import Clock, Log, Scripted, tick


def test_halting_a_running_sequence_halts_only_its_running_child() -> None:
    log = Log()
    done, running = Scripted("Done", [], log), Scripted("Run", ["RUNNING"], log)
    node = Sequence("S", [done, running])
    assert tick(node) == Status.RUNNING
    assert done.status == Status.SUCCESS
    node.stop(Status.INVALID)
    assert (running.halted, done.halted) == (1, 0)
    assert node.status == running.status == Status.INVALID
    assert done.status == Status.SUCCESS  # py_trees keeps what the finished child returned
    assert bt_status(done) == bt_status(running) == Status.INVALID  # BT.CPP: both IDLE
    assert node.index == 0


def test_a_reactive_sequence_halts_the_runner_when_an_earlier_child_fails() -> None:
    log = Log()
    work = Scripted("Work", ["RUNNING"], log)
    node = ReactiveSequence("R", [Scripted("Guard", ["SUCCESS", "FAILURE"], log), work])
    assert tick(node) == Status.RUNNING
    assert tick(node) == Status.FAILURE
    assert work.halted == 1


def test_switch_follows_its_variable_and_halts_the_case_it_leaves() -> None:
    log = Log()
    variables = DictVariables({"mode": "a"})
    a, b, default = (Scripted(n, ["RUNNING"], log) for n in ("A", "B", "Default"))
    node = Switch("Sw", [a, b, default], ["a", "b"], "mode", variables)
    assert tick(node) == Status.RUNNING
    variables.set("mode", "b")
    assert tick(node) == Status.RUNNING
    assert a.halted == 1
    variables.unset("mode")
    tick(node)
    assert log.visits == ["A RUNNING", "B RUNNING", "Default RUNNING"]
    with pytest.raises(ValueError, match="needs 3 children"):
        Switch("Bad", [a, b], ["a", "b"], "mode", variables)


@pytest.mark.parametrize(("variable", "case", "equal"), [
    ("a", "a", True), ("a", "b", False), ("2", "2.0", True), ("2.0", "2", True),
    ("1.5", "1", True),  # std::from_chars reads the leading integer, as BT.CPP does
    ("0.1", "0.2", True),  # ... so these are both 0
    ("1.5", "2.5", False), ("1e3", "1000.0000001", True), ("true", "1", False),
    ("-3", "-3", True), ("x2", "2", False),
])
def test_switch_compares_as_bt_cpp_does(variable: str, case: str, equal: bool) -> None:
    assert case_matches(variable, case) is equal


def test_set_and_unset_blackboard_on_dict_variables() -> None:
    variables = DictVariables({"src": 42})
    assert tick(SetBlackboard("Set", "hello", "greeting", variables)) == Status.SUCCESS
    assert tick(SetBlackboard("Copy", "{src}", "copy", variables)) == Status.SUCCESS
    assert (variables.get("greeting"), variables.get("copy")) == ("hello", 42)
    assert tick(UnsetBlackboard("Unset", "greeting", variables)) == Status.SUCCESS
    assert "greeting" not in variables
    with pytest.raises(KeyError, match="'nothing' named by value has no value"):
        tick(SetBlackboard("Bad", "{nothing}", "copy", variables))


def test_skip_unless_updated_ticks_the_child_once_per_write() -> None:
    log = Log()
    variables = DictVariables()
    node = SkipUnlessUpdated("Skip", Scripted("Child", ["SUCCESS"], log), "x", variables)
    tick(node)
    assert was_skipped(node) and log.visits == []  # never written
    variables.set("x", 1)
    assert tick(node) == Status.SUCCESS and not was_skipped(node)
    tick(node)
    assert was_skipped(node)
    variables.set("x", 1)  # an equal value is still a write
    tick(node)
    assert log.visits == ["Child SUCCESS", "Child SUCCESS"]


def test_wait_value_update_runs_until_a_write_and_keeps_a_running_child() -> None:
    log = Log()
    variables = DictVariables()
    node = WaitValueUpdate("Wait", Scripted("Child", ["RUNNING", "SUCCESS"], log), "x",
                           variables)
    assert tick(node) == Status.RUNNING and log.visits == []
    variables.set("x", "now")
    assert tick(node) == Status.RUNNING
    assert tick(node) == Status.SUCCESS  # the running child is ticked without a new write
    assert tick(node) == Status.RUNNING
    assert log.visits == ["Child RUNNING", "Child SUCCESS"]


def test_entry_watchers_need_versioned_variables() -> None:
    class Plain(dict):  # type: ignore[type-arg]
        def set(self, name: str, value: object) -> None:
            self[name] = value

    with pytest.raises(TypeError, match="cannot tell when 'x' was written"):
        SkipUnlessUpdated("S", py_trees.behaviours.Success("c"), "x", Plain())  # type: ignore[arg-type]


def test_blackboard_variables_count_writes_per_key() -> None:
    py_trees.blackboard.Blackboard.clear()
    writer = BlackboardVariables("w", {"x": "/ctl_test_x"}, ["x"])
    reader = BlackboardVariables("r", {"value": "/ctl_test_x"})
    assert reader.version("value") == 0
    writer.set("x", 5)
    writer.set("x", 5)
    assert reader.version("value") == 2 and reader.get("value") == 5
    writer.unset("x")
    assert reader.version("value") == 0 and "value" not in reader


def test_delay_timeout_and_sleep_read_the_clock() -> None:
    log, clock = Log(), Clock()
    delay = Delay("D", Scripted("Late", ["SUCCESS"], log), 500, clock)
    timeout = Timeout("T", Scripted("Slow", ["RUNNING"], log), 1000, clock)
    sleep = Sleep("Z", 250, clock)
    statuses = []
    for now in (0.0, 0.3, 0.6, 1.2):
        clock.now = now
        statuses.append((tick(delay), tick(timeout), tick(sleep)))
    assert statuses == [
        (Status.RUNNING, Status.RUNNING, Status.RUNNING),
        (Status.RUNNING, Status.RUNNING, Status.SUCCESS),
        (Status.SUCCESS, Status.RUNNING, Status.RUNNING),
        (Status.RUNNING, Status.FAILURE, Status.SUCCESS),
    ]
    assert sorted(log.visits) == ["Late SUCCESS"] + ["Slow RUNNING"] * 3
    assert timeout.decorated.halted == 1


def test_run_once_latch_survives_a_halt() -> None:
    log = Log()
    node = RunOnce("Once", Scripted("Child", ["FAILURE"], log), then_skip=False)
    assert tick(node) == Status.FAILURE
    node.stop(Status.INVALID)
    assert tick(node) == Status.FAILURE
    assert log.visits == ["Child FAILURE"]


def _write(tmp_path: Path, root: str) -> Path:
    path = tmp_path / "tree.yaml"
    path.write_text("format: 1\n" + ("" if root.startswith("subtrees") else "root:\n") + root)
    return path


def test_the_blackboard_nodes_share_py_trees_blackboard_entries(tmp_path: Path,
                                                                registry: Registry) -> None:
    py_trees.blackboard.Blackboard.clear()
    path = _write(tmp_path, """\
  Sequence:
    children:
      - SetBlackboard: {value: "2", output_key: mode}
      - SetBlackboard: {value: "{mode}", output_key: copy}
      - Switch2:
          variable: "{@copy}"
          case_1: "1"
          case_2: "2"
          children: [Fixed: {status: failure}, Fixed: {name: Two, status: success},
                     Fixed: {status: failure}]
      - UnsetBlackboard: {key: mode}
""")
    root = load_tree(path, {}, registry=registry).root
    assert tick(root) == Status.SUCCESS
    storage = py_trees.blackboard.Blackboard.storage
    assert storage["/copy"] == "2" and "/mode" not in storage
    assert root.children[2].children[1].status != Status.FAILURE


def test_clock_driven_kinds_use_the_context_clock(tmp_path: Path, registry: Registry) -> None:
    clock = Clock()
    path = _write(tmp_path, """\
  Sequence:
    children:
      - Delay: {delay_msec: 100, child: {Fixed: {status: success}}}
      - Timeout: {msec: 100, child: {Fixed: {status: success}}}
      - Sleep: {msec: 100}
""")
    root = load_tree(path, {CLOCK_KEY: clock}, registry=registry).root
    assert all(child.clock is clock for child in root.children)


@pytest.mark.parametrize(("root", "message"), [
    ("  Parallel:\n    success_count: 3\n    children: [Fixed: {status: success}]\n",
     "tree.yaml:3:3: error: 'success_count' 3 is more than the 1 children of this Parallel"),
    ("  ParallelAll:\n    max_failures: 2\n    children: [Fixed: {status: success}]\n",
     "'max_failures' 2 is more than"),
    ("subtrees:\n  s:\n    Parallel: {failure_count: 2, children: [Fixed: {status: success}]}"
     "\nroot:\n  subtree: s\n", "tree.yaml:4:5: error: 'failure_count' 2 is more than"),
    ("  IfThenElse:\n    children: [Fixed: {status: success}]\n",
     "tree.yaml:4:15: error: IfThenElse takes at least 2 children, got 1"),
    ("  Switch2:\n    variable: x\n    case_1: a\n    children: [Fixed: {status: success}]\n",
     "Switch2 is missing required attribute 'case_2'"),
    ("  Repeat: {num_cycles: -2, child: {Fixed: {status: success}}}\n",
     "'num_cycles' must be >= -1, got -2"),
])
def test_bad_bt_cpp_kinds_are_located_errors(tmp_path: Path, registry: Registry, root: str,
                                             message: str) -> None:
    assert message in load_problems(_write(tmp_path, root), registry)


def test_a_loop_pops_a_shared_list_and_writes_each_value() -> None:
    log = Log()
    items = [3, 4]
    variables = DictVariables({"items": items})
    node = Loop("L", Scripted("Use", ["SUCCESS"], log), None, variables,
                queue_variable="items", value="item", if_empty="SKIPPED")
    assert tick(node) == Status.RUNNING and variables.get("item") == 3
    assert items == [4]  # popped from the list the variable holds
    assert tick(node) == Status.RUNNING and variables.get("item") == 4
    tick(node)
    assert was_skipped(node) and log.visits == ["Use SUCCESS"] * 2


def test_was_entry_updated_answers_once_per_write() -> None:
    variables = DictVariables()
    node = WasEntryUpdated("W", "x", variables)
    assert tick(node) == Status.FAILURE
    variables.set("x", 0)
    assert [tick(node), tick(node)] == [Status.SUCCESS, Status.FAILURE]


def test_a_loop_item_of_the_wrong_type_is_a_located_error(tmp_path: Path,
                                                          registry: Registry) -> None:
    with pytest.raises(TreeLoadError, match=r"tree.yaml:3:3: error: cannot construct LoopInt "
                       r"'LoopInt': ValueError: invalid literal for int\(\) with base 10: 'x'"):
        load_tree(_write(tmp_path, "  LoopInt: {queue: '1;x', child: {Fixed: {status: "
                         "success}}}\n"), {}, registry=registry)
