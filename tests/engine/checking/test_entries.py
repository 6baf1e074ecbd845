"""Ports and entries in tree files: resolution per scope and every check, at line:col."""

from __future__ import annotations

from collections.abc import Callable

import pytest

from sar_framework.engine.checking.validate import ValidationResult
from sar_framework.engine.ports import NO_DEFAULT
from sar_framework.engine.spec import NodeSpec

from ..conftest import Checker
from ..port_setup import (
    PLAN_AND_FOLLOW,
    port_registry,  # noqa: F401 (pytest fixture)
)


def node(result: ValidationResult, name: str, nth: int = 0) -> NodeSpec:
    assert result.spec is not None, [str(d) for d in result.diagnostics]
    return [n for n in result.spec.nodes() if n.name == name][nth]


def keys(spec: NodeSpec) -> dict[str, str | None]:
    return {name: b.key for name, b in spec.bindings.items() if b.key is not None}


#: PLAN_AND_FOLLOW without its ``path`` entry and its subtrees: the main tree declares its
#: entries, so ``{path}`` is reported (each test adds its ``FollowIt``).
UNDECLARED_PATH = PLAN_AND_FOLLOW.replace("  path: {type: nav_msgs/msg/Path}\n", "").split(
    "subtrees:")[0]


def test_plan_then_follow_resolves(validate: Callable[..., ValidationResult]) -> None:
    result = validate(PLAN_AND_FOLLOW)
    assert result.ok, [str(d) for d in result.diagnostics]
    assert keys(node(result, "Plan")) == {"start": "/start", "goal": "/goal", "path": "/path"}
    # route -> the parent's path; pose (default {start}) and steps autoremapped to the root
    assert keys(node(result, "Follow")) == {"path": "/path", "pose": "/start", "steps": "/steps"}
    entries = result.spec.entries  # type: ignore[union-attr]
    assert list(entries) == ["/goal", "/start", "/path", "/steps"]
    assert entries["/goal"].description == "Where to go."
    assert entries["/steps"].initial == 0 and entries["/goal"].initial is NO_DEFAULT
    assert entries["/path"].type == "nav_msgs/msg/Path"


def test_undeclared_entry_in_declaring_scope(check: Checker) -> None:
    assert check(UNDECLARED_PATH + "subtrees:\n  FollowIt: {Follow: {path: '{route}'}}\n") == [
        "tree.yaml:10:38: error: port 'path' of Plan: '{path}' is not an entry of the main "
        "tree (declared: goal, start, steps)",
        "tree.yaml:11:50: error: port 'route' of subtree 'FollowIt': '{path}' is not an entry "
        "of the main tree (declared: goal, start, steps)",
    ]


def test_unknown_key_did_you_mean_and_root_key(check: Checker) -> None:
    assert check("""
        format: 1
        blackboard:
          goal: {type: geometry_msgs/msg/Point}
          path: {type: nav_msgs/msg/Path}
        root:
          sequence:
            memory: true
            children:
              - Plan: {goal: "{gaol}", path: "{path}"}
              - Follow: {path: "{path}", pose: "{@pose}"}
    """) == [
        "tree.yaml:9:9: error: port 'start' of Plan (default {start}): '{start}' is not an "
        "entry of the main tree (declared: goal, path)",
        "tree.yaml:9:22: error: port 'goal' of Plan: '{gaol}' is not an entry of the main tree "
        "(did you mean 'goal'?)",
        "tree.yaml:10:40: error: port 'pose' of Follow: '{@pose}' is not an entry of the main "
        "tree (declared: goal, path)",
    ]


def test_read_nothing_writes(check: Checker) -> None:
    assert check("""
        format: 1
        root:
          sequence:
            memory: true
            children:
              - Plan: {goal: "{goal}", start: "{here}", path: "{path}"}
              - Follow: {path: "{path}", pose: "{here}"}
    """) == [
        "tree.yaml:6:22: error: port 'goal' of Plan reads 'goal', but nothing writes it and it "
        "has no initial value (declare it under 'blackboard:' if the caller sets it)",
    ]


def test_declared_or_initial_entries_need_no_writer(check: Checker) -> None:
    assert check("""
        format: 1
        blackboard:
          goal: {type: geometry_msgs/msg/Point}
          start: {type: geometry_msgs/msg/Point}
          word: {type: str, initial: hello}
        root:
          sequence:
            memory: true
            children:
              - Plan: {goal: "{goal}", path: "{=}"}
              - Spell: {word: "{word}"}
    """) == ["tree.yaml:10:38: error: port 'path' of Plan: '{path}' is not an entry of the "
             "main tree (declared: goal, start, word)"]


def test_writer_reader_types(check: Checker) -> None:
    assert check("""
        format: 1
        root:
          sequence:
            memory: true
            children:
              - Emit: {value: "{n}"}
              - Gauge: {value: "{n}", seen: "{f}"}
              - Spell: {word: "{n}"}
              - Emit: {value: "{f}"}
    """) == [  # int -> float is allowed; int -> str is not; int into a float entry is fine
        "tree.yaml:8:23: error: port 'word' of Spell reads 'n' as str, but port 'value' of "
        "Emit at tree.yaml:6:23 writes int",
    ]


def test_declared_types(check: Checker) -> None:
    assert check("""
        format: 1
        blackboard:
          n: {type: str, initial: "a"}
          f: {type: float, initial: 2}
        root:
          sequence:
            memory: true
            children:
              - Emit: {value: "{n}"}
              - Gauge: {value: "{f}", seen: "{n}"}
              - Spell: {word: "{f}"}
    """) == [
        "tree.yaml:9:23: error: port 'value' of Emit writes int to 'n', declared str at "
        "tree.yaml:3:3",
        "tree.yaml:10:37: error: port 'seen' of Gauge writes float to 'n', declared str at "
        "tree.yaml:3:3",
        "tree.yaml:11:23: error: port 'word' of Spell reads 'f' as str, declared float at "
        "tree.yaml:4:3",
    ]


def test_literals_convert(validate: Callable[..., ValidationResult], check: Checker) -> None:
    result = validate("""
        format: 1
        root:
          Say: {text: 3, times: "4", rate: "1.5", loud: "TRUE", items: "a;b", anything: [1]}
    """)
    bound = {n: b.value for n, b in node(result, "Say").bindings.items()}
    assert bound == {"text": "3", "times": 4, "rate": 1.5, "loud": True, "items": ["a", "b"],
                     "anything": [1]}
    assert check("""
        format: 1
        root:
          Say: {times: "many", loud: "yes", rate: fast}
    """) == [
        "tree.yaml:3:16: error: port 'times': expected an int, got 'many'",
        "tree.yaml:3:30: error: port 'loud': expected a bool (true/false/1/0), got 'yes'",
        "tree.yaml:3:43: error: port 'rate': expected a float, got 'fast'",
    ]


def test_bindings_as_written(check: Checker) -> None:
    assert check("""
        format: 1
        root:
          sequence:
            memory: true
            children:
              - Say: {label: "{x}", txet: "a"}
              - Typed: {label: a, count: "{x}", source: "{y}"}
              - Plan: {goal: {goal}, path: "nowhere"}
              - Emit: {value: "{a.b}", number: 1.5}
    """) == [
        "tree.yaml:6:22: error: 'label' is a param, not a port: it cannot be bound to the "
        "entry '{x}'",
        "tree.yaml:6:29: error: unknown param or port 'txet' for plugin 'Say' "
        "(did you mean 'text'?)",
        "tree.yaml:7:34: error: 'count' must be an integer, got string '{x}' (a param, not a "
        "port: it cannot be bound to a blackboard entry)",
        "tree.yaml:7:49: error: 'source' is a param, not a port: it cannot be bound to the "
        "entry '{y}'",
        "tree.yaml:8:9: error: port 'start' of Plan (default {start}) reads 'start', but "
        "nothing writes it and it has no initial value (declare it under 'blackboard:' if the "
        "caller sets it)",
        "tree.yaml:8:22: error: port 'goal': got a mapping {goal: null}: to bind the entry, "
        "quote it: '\"{goal}\"' (unquoted, YAML reads {goal} as a mapping)",
        "tree.yaml:8:36: error: output port 'path' must be bound to an entry ('{key}'), got "
        "'nowhere'",
        "tree.yaml:9:23: error: port 'value': '{a.b}' is not a valid entry name (letters, "
        "digits and '_', not starting with a digit)",
        "tree.yaml:9:40: error: port 'number' must be bound to an integer literal, or an entry "
        "('{key}'), got number 1.5",
    ]


@pytest.mark.ros  # a message literal: the .msg files of the ROS interfaces
def test_blackboard_section(check: Checker) -> None:
    assert check("""
        format: 1
        blackboard:
          a: {type: flaot, initial: 1}
          b: {type: int, initial: "x"}
          c: {type: bool, intial: true}
          d.e: {type: int}
          f: {}
          g: {type: geometry_msgs/msg/Point, initial: 1}
        root: {Tick: {}}
    """) == [
        "tree.yaml:3:13: error: unknown type 'flaot' (did you mean 'float'?)",
        "tree.yaml:4:27: error: initial value of 'b': expected an int, got 'x'",
        "tree.yaml:5:19: error: unknown key 'intial' for 'c' (did you mean 'initial'?)",
        "tree.yaml:6:3: error: 'd.e' is not a valid entry name (letters, digits and '_', not "
        "starting with a digit)",
        "tree.yaml:7:3: error: entry 'f' needs a 'type' (one of str, int, float, bool, list, "
        "any, or pkg/msg/Type)",
        "tree.yaml:8:47: error: initial value of 'g': a geometry_msgs/msg/Point is written as "
        "a mapping of its fields (x, y, z), got 1",
    ]


SUBTREES = """
format: 1
blackboard:
  plan: {type: nav_msgs/msg/Path}
  start: {type: geometry_msgs/msg/Point}
  steps: {type: int, initial: 0}
root:
  sequence:
    memory: true
    children:
      - subtree: {tree: Go, ports: {route: "{plan}"}}
      - subtree: {tree: Go, ports: {route: "{plan}", limit: "5"}}
      - subtree: {tree: Loose, ports: {anything: "{plan}"}}
subtrees:
  Go:
    ports:
      route: {type: nav_msgs/msg/Path}
      limit: {type: int, default: 3}
    root:
      Follow: {path: "{route}", pose: "{@start}", steps: "{@steps}"}
  Loose:
    Follow: {path: "{anything}", pose: "{@start}", steps: "{_mine}"}
"""


def test_subtree_scopes_and_remapping(validate: Callable[..., ValidationResult]) -> None:
    result = validate(SUBTREES)
    first, second, third = (node(result, "Follow", i) for i in range(3))
    assert keys(first) == keys(second) == {"path": "/plan", "pose": "/start", "steps": "/steps"}
    assert keys(third) == {"path": "/plan", "pose": "/start", "steps": "/Loose@0_2/_mine"}
    entries = result.spec.entries  # type: ignore[union-attr]
    assert entries["/Go@0_0/limit"].initial == 3  # the port's default, per insertion
    assert entries["/Go@0_1/limit"].initial == 5  # a literal remap, converted
    assert "/Go@0_0/route" not in entries  # remapped, so never a key of its own


def test_subtree_use_problems(check: Checker) -> None:
    text = (SUBTREES.replace('route: "{plan}"}}\n      - subtree: {tree: Go, ports: '
                             '{route: "{plan}", limit: "5"}}',
                             'route: "{plan}", rout: "{plan}"}}\n      - subtree: {tree: Go, '
                             'ports: {route: "{plna}", limit: "x"}}'))
    assert check(text) == [
        "tree.yaml:10:60: error: subtree 'Go' has no port 'rout' (did you mean 'route'?)",
        "tree.yaml:11:44: error: port 'route' of subtree 'Go': '{plna}' is not an entry of the "
        "main tree (did you mean 'plan'?)",
        "tree.yaml:11:61: error: port 'limit' of subtree 'Go': expected an int, got 'x'",
    ]


def test_subtree_declared_entries(check: Checker) -> None:
    assert check("""
        format: 1
        root:
          subtree: {tree: Go, ports: {route: "{p}"}}
        subtrees:
          Go:
            ports:
              route: {type: nav_msgs/msg/Path}
            blackboard:
              here: {type: geometry_msgs/msg/Point}
            root:
              Follow: {path: "{route}", pose: "{here}", steps: "{stesp}"}
    """) == [  # 'here' is local (caller_sets only for the main tree's entries): pose writes it
        "tree.yaml:11:22: error: port 'path' of Follow reads 'p', but nothing writes it and it "
        "has no initial value (declare it under 'blackboard:' if the caller sets it)",
        "tree.yaml:11:56: error: port 'steps' of Follow: '{stesp}' is not an entry of subtree "
        "'Go' (declared: route, here)",
    ]


def test_autoremap_and_private_keys(validate: Callable[..., ValidationResult],
                                    check: Checker) -> None:
    text = """
        format: 1
        blackboard:
          goal: {type: geometry_msgs/msg/Point}
          start: {type: geometry_msgs/msg/Point}
        root:
          sequence:
            memory: true
            children:
              - subtree: {tree: PlanIt, autoremap: true}
              - subtree: {tree: PlanIt}
        subtrees:
          PlanIt:
            sequence:
              memory: true
              children:
                - Plan: {goal: "{goal}", path: "{_path}"}
                - Follow: {path: "{_path}"}
    """
    assert check(text) == [
        "tree.yaml:16:24: error: port 'goal' of Plan reads 'PlanIt@0_1/goal', but nothing "
        "writes it and it has no initial value (declare it under 'blackboard:' if the caller "
        "sets it)",
    ]
    result = validate(text.replace("- subtree: {tree: PlanIt}\n", "- Tick: {}\n"))
    assert keys(node(result, "Plan")) == {"start": "/start", "goal": "/goal",
                                          "path": "/PlanIt@0_0/_path"}


def test_root_key_from_a_subtree(validate: Callable[..., ValidationResult]) -> None:
    result = validate("""
        format: 1
        root:
          sequence:
            memory: true
            children:
              - Emit: {value: "{n}"}
              - subtree: Inner
        subtrees:
          Inner: {Gauge: {value: "{@n}", seen: "{n}"}}
    """)
    assert keys(node(result, "Gauge")) == {"value": "/n", "seen": "/Inner@0_1/n"}


def test_unused_definition_literals_checked(check: Checker) -> None:
    assert check("""
        format: 1
        root: {Tick: {}}
        subtrees:
          Spare: {Say: {times: "many"}}
    """) == ["tree.yaml:4:24: error: port 'times': expected an int, got 'many'"]


def test_blackboard_only_in_the_main_file(check: Checker) -> None:
    assert check(files={
        "tree.yaml": "format: 1\ninclude: [lib.yaml]\nroot: {subtree: S}\n",
        "lib.yaml": "format: 1\nblackboard:\n  x: {type: int}\nsubtrees:\n  S: {Tick: {}}\n",
    }) == ["lib.yaml:2:1: error: 'blackboard' is only read from the main tree file; declare "
           "an included subtree's ports instead"]


def test_references_unchanged(validate: Callable[..., ValidationResult]) -> None:
    result = validate("""
        format: 1
        root:
          sequence:
            memory: true
            children:
              - Fixed: {id: f}
              - Typed: {label: a, source: f}
    """)
    assert node(result, "Typed").refs["source"] is node(result, "Fixed")


def test_format_problems_worded(check: Checker) -> None:
    assert check("""
        format: 1
        blackboard: {a: 3}
        root:
          sequence:
            memory: true
            children:
              - Say: {items: {a: 1}}
              - subtree: {tree: X, portz: {}}
              - subtree: {ports: {}}
              - Emit: {value: "{}"}
        subtrees:
          X: {root: {Tick: {}}, extra: 1}
          Y: {ports: {p: {type: int, direction: output, default: 3}}, root: {Tick: {}}}
    """) == [
        "tree.yaml:2:17: error: 'a' must be a mapping such as {type: int}, got integer 3",
        "tree.yaml:7:22: error: port 'items' must be bound to a list literal, or an entry "
        "('{key}'), got a mapping",
        "tree.yaml:8:28: error: unknown attribute 'portz' for subtree (did you mean 'ports'?)",
        "tree.yaml:9:9: error: subtree is missing required attribute 'tree'",
        "tree.yaml:10:23: error: port 'value': '{}' is not a valid entry name (letters, "
        "digits and '_', not starting with a digit)",
        "tree.yaml:12:25: error: unknown key 'extra' in subtree definition 'X' (expected one "
        "of: description, ports, blackboard, root)",
        "tree.yaml:13:18: error: port 'p': an output's default must be an entry",
    ]


def test_a_required_port(check: Checker) -> None:
    assert check("format: 1\nroot: {Follow: {}}\n") == [
        "tree.yaml:2:8: error: Follow is missing required port 'path'"]


def test_a_mapping_on_a_text_port_says_text_is_fine(check: Checker) -> None:
    assert check("""
        format: 1
        root:
          sequence:
            memory: true
            children:
              - Say: {text: {word}}
              - Say: {anything: {a: 1}}
    """) == [
        "tree.yaml:6:21: error: port 'text' must be bound to a string, a number or a boolean "
        "(true or false) literal, or an entry ('{key}'), got a mapping (quote it: '\"{word}\"'; "
        "unquoted, YAML reads {word} as a mapping)",
        "tree.yaml:7:25: error: port 'anything' must be bound to a string, a number, a boolean "
        "(true or false) or a list literal, or an entry ('{key}'), got a mapping",
    ]
