"""Every BT.CPP 4 control, decorator and built-in leaf kind, ticked alike by the real
BehaviorTree.CPP and by py_trees (our behaviours), tick by tick.

Each tree uses the node kinds named after BT.CPP's IDs, scripted ``Tick`` leaves and
BT.CPP's own leaves; both transcripts (leaf visits, halts of running leaves, root status
per tick) must be equal.
The clock-driven nodes (Delay, Timeout, Sleep) run with 300 ms between ticks: the checker
sleeps, py_trees' side advances a simulated clock by the same amount; every deadline
falls 150 ms away from a tick. SkipUnlessUpdated and WaitValueUpdate name their entry
without braces: with ``{x}`` BT.CPP creates ``x`` typed ``BT::Any``, into which its
SetBlackboard then cannot write a literal (the same for SetBlackboard's ``value="{x}"``).
"""

from __future__ import annotations

import textwrap
from pathlib import Path

import pytest

from interop.scripted import Script, compare
from sar_framework.engine.nodes.control_kinds import CONTROL_KINDS
from sar_framework.engine.registry import discover

pytestmark = pytest.mark.timeout(1200)
REPO = Path(__file__).resolve().parents[2]
GENERIC = REPO / "tests" / "engine" / "plugins_for_tests" / "generic"
STEP = 0.3


def tree_file(tmp_path: Path, root: str) -> Path:
    """The tree file of a case: its root node, or its ``blackboard:`` then ``root:``."""
    path = tmp_path / "tree.yaml"
    text = textwrap.dedent(root).lstrip("\n")
    if not text.startswith("blackboard:"):
        text = "root:\n" + textwrap.indent(text, "  ")
    path.write_text("format: 1\nname: t\n" + text)
    return path


def _leaves(*names: str) -> str:
    return "[" + ", ".join(f"Tick: {{name: {n}}}" for n in names) + "]"


#: name -> (tree root, script, ticks (all of them are run), seconds between ticks).
CASES: dict[str, tuple[str, Script, int, float]] = {
    "Sequence resumes, restarts after a failure": (f"""
        Sequence:
          children: {_leaves("A", "B", "C")}
        """, {"A": ["RUNNING", "SUCCESS"], "B": ["FAILURE", "RUNNING", "SUCCESS"]}, 6, 0),
    "SequenceWithMemory retries the failed child and yields": (f"""
        SequenceWithMemory:
          children: {_leaves("A", "B", "C")}
        """, {"B": ["FAILURE", "FAILURE", "SUCCESS"], "C": ["RUNNING", "FAILURE"]}, 9, 0),
    "ReactiveSequence halts the runner": (f"""
        ReactiveSequence:
          children: {_leaves("Guard", "Work")}
        """, {"Guard": ["SUCCESS", "SUCCESS", "FAILURE"], "Work": ["RUNNING"]}, 5, 0),
    "AsyncSequence and AsyncFallback yield between children": (f"""
        AsyncSequence:
          children:
            - Tick: {{name: A}}
            - AsyncFallback:
                children: {_leaves("F1", "F2", "F3")}
            - Tick: {{name: C}}
        """, {"A": ["SUCCESS", "RUNNING", "SUCCESS", "FAILURE"], "F1": ["FAILURE"],
              "F2": ["RUNNING", "FAILURE", "SUCCESS"], "F3": ["FAILURE", "SUCCESS"]}, 14, 0),
    "Fallback": (f"""
        Fallback:
          children: {_leaves("A", "B", "C")}
        """, {"A": ["FAILURE"], "B": ["RUNNING", "FAILURE", "SUCCESS"],
              "C": ["RUNNING", "FAILURE"]}, 7, 0),
    "ReactiveFallback preempts": (f"""
        ReactiveFallback:
          children: {_leaves("High", "Low")}
        """, {"High": ["FAILURE", "FAILURE", "SUCCESS", "FAILURE"], "Low": ["RUNNING"]}, 6, 0),
    "Parallel, default thresholds": (f"""
        Parallel:
          children: {_leaves("P1", "P2", "P3")}
        """, {"P1": ["SUCCESS"], "P2": ["RUNNING", "SUCCESS"],
              "P3": ["RUNNING", "RUNNING", "FAILURE", "RUNNING", "SUCCESS"]}, 8, 0),
    "Parallel, two of three": (f"""
        Parallel:
          success_count: 2
          failure_count: 2
          children: {_leaves("P1", "P2", "P3")}
        """, {"P1": ["RUNNING", "SUCCESS", "FAILURE"], "P2": ["FAILURE", "RUNNING"],
              "P3": ["RUNNING", "RUNNING", "SUCCESS", "FAILURE"]}, 8, 0),
    "Parallel, negative thresholds": (f"""
        Parallel:
          success_count: -2
          failure_count: -1
          children: {_leaves("P1", "P2", "P3")}
        """, {"P1": ["FAILURE", "RUNNING", "SUCCESS"], "P2": ["RUNNING", "SUCCESS"],
              "P3": ["RUNNING"]}, 8, 0),
    "ParallelAll": (f"""
        ParallelAll:
          max_failures: 2
          children: {_leaves("P1", "P2", "P3")}
        """, {"P1": ["FAILURE", "SUCCESS"], "P2": ["RUNNING", "RUNNING", "FAILURE"],
              "P3": ["RUNNING", "SUCCESS", "RUNNING", "FAILURE"]}, 8, 0),
    "IfThenElse with and without else": (f"""
        Sequence:
          children:
            - IfThenElse:
                children: {_leaves("If", "Then", "Else")}
            - IfThenElse:
                children: {_leaves("If2", "Then2")}
        """, {"If": ["RUNNING", "SUCCESS", "FAILURE"], "Then": ["RUNNING", "SUCCESS"],
              "Else": ["SUCCESS", "FAILURE"], "If2": ["SUCCESS", "FAILURE"],
              "Then2": ["RUNNING", "SUCCESS"]}, 8, 0),
    "WhileDoElse switches branch": (f"""
        WhileDoElse:
          children: {_leaves("While", "Do", "Else")}
        """, {"While": ["SUCCESS", "SUCCESS", "FAILURE", "RUNNING", "FAILURE", "SUCCESS"],
              "Do": ["RUNNING"], "Else": ["RUNNING", "SUCCESS"]}, 8, 0),
    "WhileDoElse without else": (f"""
        WhileDoElse:
          children: {_leaves("While", "Do")}
        """, {"While": ["SUCCESS", "FAILURE", "SUCCESS"], "Do": ["RUNNING", "SUCCESS"]}, 4, 0),
    "Switch2 on a literal": (f"""
        Switch2:
          variable: "2.0"
          case_1: one
          case_2: "2"
          children: {_leaves("One", "Two", "Other")}
        """, {"Two": ["RUNNING", "SUCCESS"]}, 3, 0),
    "Switch3 on an entry set by SetBlackboard": (f"""
        ReactiveSequence:
          children:
            - IfThenElse:
                children:
                  - Tick: {{name: Pick}}
                  - SetBlackboard: {{value: b, output_key: mode}}
                  - SetBlackboard: {{value: "7.0", output_key: mode}}
            - Switch3:
                variable: "{{mode}}"
                case_1: a
                case_2: b
                case_3: "7"
                children: {_leaves("A", "B", "Seven", "Default")}
        """, {"Pick": ["SUCCESS", "SUCCESS", "FAILURE", "FAILURE", "SUCCESS"],
              "B": ["RUNNING", "RUNNING", "SUCCESS"], "Seven": ["RUNNING"]}, 6, 0),
    "Switch2 with cases read from entries": (f"""
        blackboard:
          unset: {{type: str, description: Nobody sets it; the case is passed over.}}
          wanted: {{type: str}}
        root:
          Sequence:
            children:
              - IfThenElse:
                  children:
                    - Tick: {{name: Pick}}
                    - SetBlackboard: {{value: b, output_key: wanted}}
                    - SetBlackboard: {{value: c, output_key: wanted}}
              - Switch2:
                  variable: b
                  case_1: "{{unset}}"
                  case_2: "{{wanted}}"
                  children: {_leaves("One", "Two", "Other")}
        """, {"Pick": ["SUCCESS", "FAILURE", "SUCCESS"]}, 3, 0),
    "Switch4, 5 and 6 fall back to the default": (f"""
        blackboard:
          missing: {{type: str, description: The caller could set it; nobody does.}}
        root:
          Sequence:
           children:
            - Switch4:
                variable: "{{missing}}"
                case_1: a
                case_2: b
                case_3: c
                case_4: d
                children: {_leaves("S4a", "S4b", "S4c", "S4d", "S4default")}
            - Switch5:
                variable: "5"
                case_1: "1"
                case_2: "2"
                case_3: "3"
                case_4: "4"
                case_5: "5"
                children: {_leaves("S5a", "S5b", "S5c", "S5d", "S5e", "S5default")}
            - Switch6:
                variable: x
                case_1: "1"
                case_2: "2"
                case_3: "3"
                case_4: "4"
                case_5: "5"
                case_6: "6"
                children: {_leaves("S6a", "S6b", "S6c", "S6d", "S6e", "S6f", "S6default")}
        """, {}, 2, 0),
    "Inverter, ForceSuccess, ForceFailure": ("""
        Fallback:
          children:
            - Inverter: {child: {Tick: {name: Inv}}}
            - ForceFailure: {child: {Tick: {name: FF}}}
            - ForceSuccess: {child: {Tick: {name: FS}}}
            - Tick: {name: Never}
        """, {"Inv": ["SUCCESS", "RUNNING", "FAILURE"], "FF": ["RUNNING", "SUCCESS"],
              "FS": ["FAILURE"]}, 5, 0),
    "KeepRunningUntilFailure": ("""
        KeepRunningUntilFailure:
          child: {Tick: {name: Loop}}
        """, {"Loop": ["SUCCESS", "RUNNING", "SUCCESS", "FAILURE"]}, 6, 0),
    "Repeat and RetryUntilSuccessful": ("""
        Sequence:
          children:
            - Repeat:
                num_cycles: 3
                child: {Tick: {name: Again}}
            - RetryUntilSuccessful:
                num_attempts: 3
                child: {Tick: {name: Flaky}}
        """, {"Again": ["RUNNING", "SUCCESS", "SUCCESS", "RUNNING", "SUCCESS"],
              "Flaky": ["RUNNING", "FAILURE", "FAILURE", "SUCCESS", "FAILURE"]}, 12, 0),
    "RunOnce skips, or repeats its result": ("""
        Fallback:
          children:
            - RunOnce: {child: {Tick: {name: SkipLater}}}
            - RunOnce: {then_skip: false, child: {Tick: {name: KeepResult}}}
            - Tick: {name: Last}
        """, {"SkipLater": ["RUNNING", "FAILURE", "SUCCESS"], "KeepResult": ["FAILURE"],
              "Last": ["SUCCESS", "FAILURE"]}, 5, 0),
    "SKIPPED through the composites": ("""
        Sequence:
          children:
            - ReactiveSequence:
                children:
                  - RunOnce: {child: {Tick: {name: R1}}}
                  - Tick: {name: Work}
            - Parallel:
                children:
                  - RunOnce: {child: {Tick: {name: R2}}}
                  - Tick: {name: P}
            - ParallelAll:
                children:
                  - RunOnce: {child: {Tick: {name: R3}}}
                  - Tick: {name: Q}
            - Fallback:
                children:
                  - RunOnce: {child: {AlwaysFailure: {}}}
                  - Inverter: {child: {RunOnce: {child: {Tick: {name: R4}}}}}
        """, {"Work": ["RUNNING", "SUCCESS"], "P": ["RUNNING", "SUCCESS", "FAILURE"],
              "Q": ["SUCCESS"]}, 7, 0),
    "skipped children count as BT.CPP counts them": ("""
        Sequence:
          children:
            - Parallel:
                children:
                  - RunOnce: {child: {Tick: {name: R1}}}
                  - Tick: {name: P}
            - Fallback:
                children:
                  - Sequence:
                      children:
                        - RunOnce: {child: {Tick: {name: R2}}}
                        - RunOnce: {child: {AlwaysSuccess: {}}}
                  - Tick: {name: F}
            - ParallelAll:
                children:
                  - RunOnce: {child: {Tick: {name: R3}}}
                  - IfThenElse:
                      children:
                        - Tick: {name: If}
                        - RunOnce: {child: {Tick: {name: R4}}}
                        - Tick: {name: Else}
        """, {"P": ["SUCCESS", "RUNNING", "SUCCESS"], "F": ["FAILURE", "SUCCESS"],
              "If": ["SUCCESS", "SUCCESS", "FAILURE"]}, 6, 0),
    "SkipUnlessUpdated, UnsetBlackboard, AlwaysSuccess": ("""
        Sequence:
          children:
            - IfThenElse:
                children:
                  - Tick: {name: Write}
                  - SetBlackboard: {value: "1", output_key: x}
                  - IfThenElse:
                      children:
                        - Tick: {name: Erase}
                        - UnsetBlackboard: {key: x}
                        - AlwaysSuccess: {}
            - SkipUnlessUpdated:
                entry: x
                child: {Tick: {name: OnUpdate}}
            - Tick: {name: After}
        """, {"Write": ["SUCCESS", "FAILURE", "SUCCESS", "SUCCESS", "FAILURE", "FAILURE",
                        "SUCCESS"],
              "Erase": ["FAILURE", "FAILURE", "SUCCESS", "FAILURE"],
              "OnUpdate": ["SUCCESS", "RUNNING", "SUCCESS"]}, 8, 0),
    "WaitValueUpdate": ("""
        ReactiveSequence:
          children:
            - IfThenElse:
                children:
                  - Tick: {name: Write}
                  - SetBlackboard: {value: "4", output_key: y}
                  - AlwaysSuccess: {}
            - WaitValueUpdate:
                entry: y
                child: {Tick: {name: OnUpdate}}
        """, {"Write": ["FAILURE", "FAILURE", "SUCCESS", "FAILURE", "SUCCESS", "FAILURE"],
              "OnUpdate": ["RUNNING", "SUCCESS"]}, 8, 0),
    "LoopString feeds a Switch, then reports if_empty": (f"""
        LoopString:
          queue: "b;x;a;b"
          value: "{{item}}"
          if_empty: FAILURE
          child:
            Switch2:
              variable: "{{item}}"
              case_1: a
              case_2: b
              children: {_leaves("A", "B", "Other")}
        """, {"B": ["RUNNING", "SUCCESS"], "A": ["FAILURE", "SUCCESS"]}, 10, 0),
    "LoopInt, LoopDouble and LoopBool": ("""
        Sequence:
          children:
            - LoopInt: {queue: "1;2;3", child: {Tick: {name: Int}}}
            - LoopDouble: {queue: "0.5;1e3", if_empty: SKIPPED, child: {Tick: {name: Real}}}
            - LoopBool: {queue: "true;0", value: "{flag}", child: {Tick: {name: Flag}}}
        """, {"Int": ["SUCCESS", "RUNNING", "SUCCESS"], "Flag": ["FAILURE", "SUCCESS"]}, 12, 0),
    "WasEntryUpdated": ("""
        Sequence:
          children:
            - IfThenElse:
                children:
                  - Tick: {name: Write}
                  - SetBlackboard: {value: "1", output_key: x}
                  - AlwaysSuccess: {}
            - Fallback:
                children:
                  - WasEntryUpdated: {entry: x}
                  - Tick: {name: NotUpdated}
        """, {"Write": ["FAILURE", "SUCCESS", "FAILURE", "SUCCESS", "SUCCESS"]}, 6, 0),
    "a preempting ReactiveFallback halts a deep branch": ("""
        ReactiveFallback:
          children:
            - Tick: {name: Stop}
            - SequenceWithMemory:
                children:
                  - Tick: {name: M1}
                  - IfThenElse:
                      children:
                        - Tick: {name: C}
                        - Repeat: {num_cycles: 3, child: {Tick: {name: R}}}
                        - Tick: {name: E}
                  - Parallel:
                      children:
                        - KeepRunningUntilFailure: {child: {Tick: {name: P1}}}
                        - RetryUntilSuccessful: {num_attempts: 2, child: {Tick: {name: P2}}}
        """, {"Stop": ["FAILURE"] * 3 + ["SUCCESS"] + ["FAILURE"] * 6 + ["SUCCESS", "FAILURE"],
              "R": ["RUNNING", "SUCCESS", "RUNNING", "RUNNING", "SUCCESS", "SUCCESS"],
              "P1": ["RUNNING"], "P2": ["FAILURE", "RUNNING"]}, 16, 0),
    "Delay": ("""
        Delay:
          delay_msec: 450
          child: {Tick: {name: Late}}
        """, {"Late": ["RUNNING", "SUCCESS"]}, 6, STEP),
    "Timeout": ("""
        Sequence:
          children:
            - Timeout:
                msec: 450
                child: {Tick: {name: Slow}}
            - Timeout:
                msec: 0
                child: {Tick: {name: Unbounded}}
        """, {"Slow": ["RUNNING", "RUNNING", "RUNNING", "RUNNING", "SUCCESS"],
              "Unbounded": ["RUNNING", "RUNNING", "RUNNING", "SUCCESS"]}, 10, STEP),
    "Timeout msec and Repeat num_cycles read from entries": ("""
        blackboard:
          cycles: {type: int, initial: 2}
          t: {type: int}
        root:
          Sequence:
            children:
              - Script: {code: "t := 450"}
              - Timeout:
                  msec: "{t}"
                  child: {Tick: {name: Slow}}
              - Repeat:
                  num_cycles: "{cycles}"
                  child: {Tick: {name: Again}}
              - Script: {code: "t := 0; cycles := 1"}
              - Timeout:
                  msec: "{t}"
                  child: {Tick: {name: Unbounded}}
              - Repeat:
                  num_cycles: "{cycles}"
                  child: {Tick: {name: Once}}
        """, {"Slow": ["RUNNING", "RUNNING", "SUCCESS"],
              "Again": ["RUNNING", "SUCCESS", "SUCCESS"],
              "Unbounded": ["RUNNING", "RUNNING", "RUNNING", "SUCCESS"]}, 12, STEP),
    "Parallel thresholds and RunOnce then_skip read from entries": ("""
        blackboard:
          need: {type: int, initial: 2}
          fails: {type: int, initial: -1}
          skip: {type: bool, initial: false}
        root:
          Sequence:
            children:
              - Parallel:
                  success_count: "{need}"
                  failure_count: "{fails}"
                  children:
                    - Tick: {name: P1}
                    - Tick: {name: P2}
                    - Tick: {name: P3}
              - ParallelAll:
                  max_failures: "{need}"
                  children:
                    - Tick: {name: Q1}
                    - Tick: {name: Q2}
              - RunOnce:
                  then_skip: "{skip}"
                  child: {Tick: {name: Once}}
              - Script: {code: "need := 1; skip := true"}
        """, {"P1": ["FAILURE", "SUCCESS"], "P2": ["RUNNING", "SUCCESS"],
              "P3": ["FAILURE", "FAILURE", "RUNNING"], "Q1": ["FAILURE", "FAILURE"],
              "Q2": ["FAILURE", "SUCCESS"], "Once": ["FAILURE", "SUCCESS"]}, 8, 0),
    "Pre/post-conditions on a SubTree, in the parent's scope": ("""
        blackboard:
          busy: {type: bool, initial: true}
          count: {type: int, initial: 0}
        subtrees:
          Work:
            blackboard:
              busy: {type: bool, initial: false, description: Not the parent's.}
            root:
              Tick: {name: W}
        root:
          Sequence:
            children:
              - subtree: {tree: Work, _skipIf: busy, _post: "count += 1"}
              - Script: {code: "busy = !busy"}
              - subtree: {tree: Work, _failureIf: "count >= 2", _onSuccess: "busy = true"}
        """, {"W": ["SUCCESS", "RUNNING", "SUCCESS", "FAILURE", "SUCCESS"]}, 6, 0),
    "Sleep": ("""
        Sequence:
          children:
            - Tick: {name: Before}
            - Sleep: {msec: 450}
            - Sleep: {msec: 0}
            - Tick: {name: After}
        """, {}, 6, STEP),
    "Sleep keeps its SUCCESS until reset": ("""
        WhileDoElse:
          children:
            - Sleep: {msec: 450}
            - Tick: {name: Do}
            - Tick: {name: Else}
        """, {"Do": ["RUNNING", "RUNNING", "SUCCESS", "RUNNING"]}, 7, STEP),
}


@pytest.mark.parametrize("case", CASES.values(), ids=CASES.keys())
def test_bt_cpp_kinds_tick_alike_in_btcpp(case: tuple[str, Script, int, float],
                                          btcpp_checker: Path, tmp_path: Path) -> None:
    root, script, ticks, step = case
    registry = discover([GENERIC], builtins=False, entry_points=False)
    compare(tree_file(tmp_path, root), registry, btcpp_checker, script, max_ticks=ticks,
            all_ticks=True, tick_seconds=step, halts=True)


def test_every_bt_cpp_kind_is_checked() -> None:
    used = " ".join(root for root, *_ in CASES.values())
    missing = {k.key for k in CONTROL_KINDS if f"{k.key}:" not in used}
    assert missing == set()
