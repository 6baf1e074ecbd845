"""Ten construct trees of our own (``fixtures/constructs/``) that together cover the tree
language, each end to end: it validates, renders (SVG, with data edges),
exports to BT.CPP XML, re-imports to the same tree, and ticks as BehaviorTree.CPP 4.7.3
does with scripted leaves (the checker; transcripts of leaf visits, halts and root status
per tick must be equal).

| tree | constructs |
|---|---|
| 01_ports_blackboard | leaf ports bound to ``{key}``, literals and ``{=}``; ``blackboard:`` |
| 02_subtree_scopes | subtree ``ports:`` remapped and given literals, ``autoremap``, ``{@key}`` |
| 03_scripts | Script, ScriptCondition, Precondition (else FAILURE, SUCCESS, SKIPPED, RUNNING) |
| 04_preconditions | ``_skipIf _successIf _failureIf _while`` (halting a running branch) |
| 05_postconditions | ``_onSuccess _onFailure _onHalted _post`` |
| 06_skipped | a SKIPPED child in every composite; all children skipped |
| 07_memory_parallel | SequenceWithMemory, Parallel thresholds, ParallelAll |
| 08_conditionals | IfThenElse, WhileDoElse, Switch3, Switch2's default |
| 09_once_timing | RunOnce ``then_skip`` true and false, Delay, Timeout (300 ms a tick) |
| 10_nav2_controls | RecoveryNode, PipelineSequence, RoundRobin, RateController, SingleTrigger |

Nav2's nodes are not in BT.CPP, so ``10_nav2_controls`` is compared with transcripts
written by hand from Nav2 Jazzy's sources (and, besides, with the checker's stand-ins for
them, ``btcpp_checker/nav2_standins.h``) (``nav2_behavior_tree/plugins/control`` and
``decorator``: recovery_node.cpp, pipeline_sequence.cpp, round_robin_node.cpp,
rate_controller.cpp, single_trigger_node.cpp), traced in the comments beside them.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
import yaml

from interop.scripted import Script, compare, run_py_trees, scripted_registry
from sar_framework.cli import main
from sar_framework.engine.api import load_spec
from sar_framework.engine.registry import discover
from sar_framework.engine.spec import NodeSpec
from sar_framework.interop.btcpp_export import export_btcpp
from sar_framework.interop.btcpp_import import import_btcpp
from sar_framework.interop.xml_source import read_xml

pytestmark = pytest.mark.timeout(1200)
REPO = Path(__file__).resolve().parents[2]
CONSTRUCTS = REPO / "tests" / "interop" / "fixtures" / "constructs"
PLUGINS = [REPO / "tests" / "engine" / "plugins_for_tests" / "generic",
           CONSTRUCTS / "construct_leaves.py"]
TREES = sorted(CONSTRUCTS.glob("*.yaml"))
NAV2_ONLY = {"10_nav2_controls"}


class Run:
    """One scripted run: the script, ticks, all ticks or until done, clock, halts."""

    def __init__(self, script: Script, ticks: int = 20, *, all_ticks: bool = False,
                 tick_seconds: float = 0.0, halts: bool = True) -> None:
        self.script = script
        self.ticks = ticks
        self.all_ticks = all_ticks
        self.tick_seconds = tick_seconds
        self.halts = halts


RUNS: dict[str, list[Run]] = {
    "01_ports_blackboard": [Run({"Step": ["FAILURE", "SUCCESS"]}),
                            Run({"Step": ["RUNNING", "SUCCESS"]})],
    "02_subtree_scopes": [Run({}), Run({"CountTick": ["FAILURE"]}),
                          Run({"AutoTick": ["RUNNING", "SUCCESS"]})],
    "03_scripts": [Run({"Work": ["RUNNING", "RUNNING", "SUCCESS"]}), Run({"Fast": ["FAILURE"]})],
    "04_preconditions": [Run({"Long": ["RUNNING"]}), Run({"Backup": ["FAILURE"]})],
    "05_postconditions": [
        Run({"B": ["FAILURE"], "Trigger": ["FAILURE", "SUCCESS"], "Runner": ["RUNNING"]}),
        Run({"B": ["FAILURE"], "Trigger": ["FAILURE"], "Runner": ["RUNNING", "SUCCESS"]}),
    ],
    "06_skipped": [Run({}), Run({"Cond": ["FAILURE"], "P2": ["RUNNING", "SUCCESS"],
                                "Q2": ["RUNNING", "FAILURE"]})],
    "07_memory_parallel": [
        Run({"Second": ["FAILURE", "SUCCESS"], "P2": ["FAILURE"], "P3": ["RUNNING", "SUCCESS"],
             "Q2": ["FAILURE"], "A1": ["FAILURE"], "A3": ["RUNNING", "SUCCESS"]}),
        Run({"P1": ["FAILURE"], "P2": ["RUNNING", "FAILURE"]}),
    ],
    "08_conditionals": [
        Run({"IsReady": ["FAILURE"], "Healthy": ["SUCCESS", "FAILURE"], "Work": ["RUNNING"]}),
        Run({"Go": ["RUNNING", "SUCCESS"], "Healthy": ["FAILURE"], "Repair": ["FAILURE"]}),
    ],
    "09_once_timing": [
        Run({"Calibrate": ["RUNNING", "SUCCESS"], "Slow": ["RUNNING"]}, 8, all_ticks=True,
            tick_seconds=0.3),
        Run({"Setup": ["FAILURE", "SUCCESS"], "Slow": ["RUNNING", "SUCCESS"]}, 8,
            all_ticks=True, tick_seconds=0.3),
    ],
}


def registry() -> Any:
    """Tick and Probe (and the other test plugins), and Nav2's controls and decorators."""
    return discover([*(str(p) for p in PLUGINS), "sar_plugins.nav2"], builtins=False,
                    entry_points=False)


def shape(node: NodeSpec) -> tuple[Any, ...]:
    """Kinds, names, attributes, scripts, subtree insertions, bound entries, children."""
    bindings = sorted((name, b.key, str(b.value)) for name, b in node.bindings.items())
    scripts = sorted((name, s.text) for name, s in node.scripts.items())
    ports = sorted((k, str(v)) for k, v in (node.insertion.get("ports") or {}).items())
    return (node.kind, node.name, node.subtree, sorted(node.attrs.items()), bindings, scripts,
            ports, bool(node.insertion.get("autoremap")), sorted(node.script_keys.items()),
            [shape(child) for child in node.children])


def test_the_ten_trees_are_there() -> None:
    assert [t.stem[:2] for t in TREES] == [f"{i:02d}" for i in range(1, 11)]


@pytest.mark.parametrize("tree", TREES, ids=[t.stem for t in TREES])
def test_construct_validates_renders_exports_and_reimports(
        tree: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    plugin_args = [arg for p in PLUGINS for arg in ("--plugin-path", str(p))]
    assert main(["validate", str(tree), *plugin_args]) == 0, capsys.readouterr().err
    svg = tmp_path / f"{tree.stem}.svg"
    assert main(["render", str(tree), "--data-edges", "-o", str(svg),
                 *plugin_args]) == 0, capsys.readouterr().err
    assert "<svg" in svg.read_text()
    plugins = registry()
    spec = load_spec(tree, registry=plugins)
    xml = tmp_path / f"{tree.stem}.xml"
    xml.write_text(export_btcpp(spec, plugins))
    result = import_btcpp(read_xml(xml), str(xml), plugins)
    assert result.problems == [] and result.drafts == {}, result.problems
    again = tmp_path / f"{tree.stem}.yaml"
    assert result.document is not None
    again.write_text(yaml.safe_dump(result.document, sort_keys=False))
    assert shape(load_spec(again, registry=plugins).root) == shape(spec.root)


CASES = [(tree, index) for tree in TREES if tree.stem not in NAV2_ONLY
         for index in range(len(RUNS[tree.stem]))]


@pytest.mark.parametrize(("tree", "index"), CASES,
                         ids=[f"{t.stem}-{i}" for t, i in CASES])
def test_construct_ticks_as_btcpp_does(tree: Path, index: int, tmp_path: Path,
                                       btcpp_checker: Path) -> None:
    run = RUNS[tree.stem][index]
    copy = tmp_path / tree.name
    copy.write_text(tree.read_text())
    compare(copy, registry(), btcpp_checker, run.script, max_ticks=run.ticks,
            all_ticks=run.all_ticks, tick_seconds=run.tick_seconds, halts=run.halts)


#: Nav2's nodes, traced by hand from Nav2 Jazzy's sources with BT.CPP 4's ControlNode
#: (``haltChild`` halts a RUNNING child only, then resets its status to IDLE).
NAV2_RUNS: list[tuple[Script, list[str]]] = [
    # Follow runs for ever. Tick 2: RateController is not IDLE (it returned SUCCESS) and
    # its 1 s period has not passed: RUNNING, which PipelineSequence passes over (index 0
    # is before the furthest child that ran). SingleTrigger is not IDLE either and has
    # fired: FAILURE. PipelineSequence halts its children (Follow) and fails; RecoveryNode
    # (retries 0 < 2) ticks RoundRobin: Clear succeeds (the next turn is Spin's), a retry
    # is counted, and the pipeline runs again from IDLE within the same tick. Tick 3 the
    # same with Spin. Tick 4: the third failure finds retries 2 = number_of_retries: FAILURE.
    ({"Follow": ["RUNNING"]}, [
        "visit Plan SUCCESS", "visit Announce SUCCESS", "visit Follow RUNNING",
        "tick 1 RUNNING",
        "halt Follow", "visit Clear SUCCESS", "visit Plan SUCCESS", "visit Announce SUCCESS",
        "visit Follow RUNNING", "tick 2 RUNNING",
        "halt Follow", "visit Spin SUCCESS", "visit Plan SUCCESS", "visit Announce SUCCESS",
        "visit Follow RUNNING", "tick 3 RUNNING",
        "halt Follow", "tick 4 FAILURE"]),
    # Announce runs four ticks: SingleTrigger re-ticks its running child; RateController
    # (started at 0 s) returns RUNNING until its period has passed: Plan again at 1.2 s.
    # Tick 6: SingleTrigger has fired, FAILURE; one recovery (Clear), then the pipeline from
    # IDLE: Plan, Announce, Follow succeeds; RecoveryNode succeeds.
    ({"Announce": ["RUNNING", "RUNNING", "RUNNING", "RUNNING", "SUCCESS"],
      "Follow": ["RUNNING", "SUCCESS"]}, [
        "visit Plan SUCCESS", "visit Announce RUNNING", "tick 1 RUNNING",
        "visit Announce RUNNING", "tick 2 RUNNING",
        "visit Announce RUNNING", "tick 3 RUNNING",
        "visit Announce RUNNING", "tick 4 RUNNING",
        "visit Plan SUCCESS", "visit Announce SUCCESS", "visit Follow RUNNING",
        "tick 5 RUNNING",
        "halt Follow", "visit Clear SUCCESS", "visit Plan SUCCESS", "visit Announce SUCCESS",
        "visit Follow SUCCESS", "tick 6 SUCCESS"]),
    # The action fails at once, three times: Clear, Spin, then FAILURE (2 retries).
    ({"Plan": ["FAILURE"]}, [
        "visit Plan FAILURE", "visit Clear SUCCESS", "visit Plan FAILURE",
        "visit Spin SUCCESS", "visit Plan FAILURE", "tick 1 FAILURE"]),
]


@pytest.mark.parametrize("index", range(len(NAV2_RUNS)), ids=["trigger", "rate", "fails"])
def test_nav2_construct_ticks_as_the_checkers_stand_ins(index: int, tmp_path: Path,
                                                        btcpp_checker: Path) -> None:
    """And BT.CPP with the checker's Nav2 stand-ins (btcpp_checker/nav2_standins.h) agrees."""
    copy = tmp_path / "10_nav2_controls.yaml"
    copy.write_text((CONSTRUCTS / copy.name).read_text())
    ours = compare(copy, registry(), btcpp_checker, NAV2_RUNS[index][0], max_ticks=10,
                   tick_seconds=0.3, halts=True)
    assert ours == NAV2_RUNS[index][1]


@pytest.mark.parametrize(("script", "expected"), NAV2_RUNS, ids=["trigger", "rate", "fails"])
def test_nav2_construct_ticks_as_nav2_source_says(script: Script, expected: list[str],
                                                  tmp_path: Path) -> None:
    """Ours against the transcripts traced by hand from Nav2's sources (above)."""
    tree = CONSTRUCTS / "10_nav2_controls.yaml"
    assert run_py_trees(tree, scripted_registry(registry()), script, 10, tick_seconds=0.3,
                        halts=True) == expected
