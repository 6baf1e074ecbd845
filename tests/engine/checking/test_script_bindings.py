"""Scripts in tree files: Script, ScriptCondition, Precondition and the pre/post-conditions,
their variables resolved like ports and checked with them, errors at file columns."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import py_trees

from sar_framework.engine.api import load_tree
from sar_framework.engine.checking.validate import ValidationResult
from sar_framework.engine.registry import Registry

from ..conftest import Checker, write
from ..port_setup import clean_blackboard, port_registry  # noqa: F401 (pytest fixtures)

Blackboard = py_trees.blackboard.Blackboard
Status = py_trees.common.Status


COUNTING = """
format: 1
blackboard:
  count: {type: int, initial: 0}
  done: {type: bool, initial: false}
  misses: {type: int, initial: 0}
  posted: {type: bool, initial: false}
root:
  sequence:
    memory: false
    children:
      - Script: {code: "count := count + 1; @done := count >= 3"}
      - ScriptCondition: {code: "done", _onFailure: "misses += 1"}
      - Precondition:
          if: "count == 3"
          else: SKIPPED
          child: {Tick: {_post: "posted = true"}}
"""


def test_scripts_tick_on_the_blackboard(tree_dir: Path, registry: Registry) -> None:
    tree = load_tree(write(tree_dir, "tree.yaml", COUNTING), registry=registry)
    seen = []
    for _ in range(4):
        tree.root.tick_once()
        seen.append((tree.root.status, *(Blackboard.get(f"/{k}")
                                         for k in ("count", "done", "misses", "posted"))))
    assert seen == [
        (Status.FAILURE, 1, False, 1, False),
        (Status.FAILURE, 2, False, 2, False),
        (Status.SUCCESS, 3, True, 2, True),
        (Status.SUCCESS, 4, True, 2, True),  # 'if' is false: SKIPPED, the sequence goes on
    ]
    wrapper = tree.behaviours["0.1"]  # a node with conditions maps to their wrapper
    assert type(wrapper).__name__ == "PrePostConditions"
    assert type(wrapper.decorated).__name__ == "ScriptCondition"


def test_script_errors_at_file_columns(check: Checker) -> None:
    assert check("""
        format: 1
        blackboard:
          count: {type: int, initial: 0}
        root:
          sequence:
            memory: false
            children:
              - Script: {code: "count := count +"}
              - Script: {code: count := 'a'}
              - ScriptCondition:
                  code: |
                    count > 1;
                    count ==
              - Tick: {_skipif: "count > 1", _while: "'yes'"}
              - Script: {code: 'count := "x" + 1'}
    """) == [
        "tree.yaml:8:41: error: script 'code' of Script: the script ends in the middle of "
        "an expression",
        "tree.yaml:9:33: error: script 'code' of Script: the string 'a' is not a number "
        "(assigned to 'count', an int)",
        "tree.yaml:13:17: error: script 'code' of ScriptCondition: the script ends in the "
        "middle of an expression",
        "tree.yaml:14:16: error: unknown param '_skipif' for plugin 'Tick' "
        "(did you mean '_skipIf'?)",
        "tree.yaml:14:47: error: script '_while' of Tick: a condition must give a number or "
        "true/false, not a str",
        "tree.yaml:15:38: error: script 'code' of Script: '+' does not apply to a str and an int",
    ]


def test_script_variables_join_the_entry_checks(check: Checker) -> None:
    assert check("""
        format: 1
        root:
          sequence:
            memory: false
            children:
              - ScriptCondition: {code: "ready"}
              - Emit: {value: "{n}"}
              - Script: {code: "label := n"}
              - Spell: {word: "{label}"}
    """) == [
        "tree.yaml:6:33: error: script 'code' of ScriptCondition reads 'ready', but nothing "
        "writes it and it has no initial value (declare it under 'blackboard:' if the caller "
        "sets it)",
    ]


def test_script_names_in_a_declaring_scope(check: Checker) -> None:
    assert check("""
        format: 1
        blackboard:
          count: {type: int, initial: 0}
        root:
          Script: {code: "cuont := 1; @done := true"}
    """) == [
        "tree.yaml:5:18: error: script 'code' of Script: 'cuont' is not an entry of the main "
        "tree (did you mean 'count'?)",
        "tree.yaml:5:18: error: script 'code' of Script: '@done' is not an entry of the main "
        "tree (declared: count)",
    ]


def test_script_types_from_port_writers(check: Checker) -> None:
    assert check("""
        format: 1
        root:
          sequence:
            memory: false
            children:
              - Plan: {goal: "{here}", start: "{here}", path: "{path}"}
              - Script: {code: "here := 1"}
              - ScriptCondition: {code: "path + 1"}
    """) == [
        "tree.yaml:8:39: error: script 'code' of ScriptCondition: '+' does not apply to a "
        "nav_msgs/msg/Path and an int",
    ]


def test_scripts_in_subtree_scopes(validate: Callable[..., ValidationResult]) -> None:
    result = validate("""
        format: 1
        blackboard:
          tries: {type: int, initial: 0}
        root:
          sequence:
            memory: false
            children:
              - subtree: {tree: Try, autoremap: true}
              - subtree: Try
        subtrees:
          Try:
            Script: {code: "tries += 1; _local := 2; @tries += _local"}
    """)
    assert result.ok, [str(d) for d in result.diagnostics]
    assert result.spec is not None
    first, second = (n for n in result.spec.nodes() if n.kind == "Script")
    assert first.script_keys == {"tries": "/tries", "_local": "/Try@0_0/_local",
                                 "@tries": "/tries"}
    assert second.script_keys["tries"] == "/Try@0_1/tries"


def test_conditions_on_a_leaf_with_ports(tree_dir: Path, registry: Registry) -> None:
    tree = load_tree(write(tree_dir, "tree.yaml", """
        format: 1
        root:
          Emit: {value: "{n}", number: 5, _skipIf: "@skip == 1", _onSuccess: "seen := n"}
        blackboard:
          skip: {type: int, initial: 1}
          n: {type: int}
          seen: {type: int}
    """), registry=registry)
    tree.root.tick_once()
    assert tree.root.status is Status.SUCCESS and "/n" not in Blackboard.storage
    Blackboard.set("/skip", 0)
    tree.root.tick_once()
    assert Blackboard.get("/n") == 5 and Blackboard.get("/seen") == 5


def test_a_script_reading_an_entry_nothing_writes(check: Checker) -> None:
    # BT.CPP fails when the condition ticks; validation says so, at the script, with the
    # entry the script probably meant.
    assert check("""
        format: 1
        root:
          sequence:
            memory: false
            children:
              - Script: {code: "target_reached := true"}
              - ScriptCondition: {code: "target_ready"}
              - Tick: {_skipIf: "!target_ready"}
    """) == [
        "tree.yaml:7:33: error: script 'code' of ScriptCondition reads 'target_ready', but "
        "nothing writes it and it has no initial value (did you mean 'target_reached'?)",
        "tree.yaml:8:25: error: script '_skipIf' of Tick reads 'target_ready', but nothing "
        "writes it and it has no initial value (did you mean 'target_reached'?)",
    ]
