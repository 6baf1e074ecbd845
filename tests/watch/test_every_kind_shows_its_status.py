"""Every node kind shows the status it returned: ``tip()``, snapshots, status and events agree.

Every node kind we have is ticked with scripted leaves through the runner's own machinery:
py_trees_ros's ``BehaviourTree`` (as :func:`.create_behaviour_tree` makes it), the status
file writer emitting the leaves' ``status`` events and its ``cancel`` records, the status
topic (``sar-tree watch``, the studio and the recording read it) and a snapshot stream
opened and read by the watcher's :class:`.SnapshotFeed`, as ``py-trees-tree-watcher`` opens
one. The trees are the BehaviorTree.CPP checks' own (``tests/interop``: every BT.CPP
control, decorator and leaf, the constructs with the scripted nodes and pre/post
conditions, Nav2's navigator trees with their controls and decorators) plus py_trees' own
kinds, alone and mixed with BT.CPP's. After every tick:

- ``tip()`` of the root, and of every node that is not INVALID, is a behaviour (py_trees_ros
  publishes no snapshot when the root has none);
- the snapshot of that tick arrives, and its statuses equal the status topic's, node for node;
- each leaf's snapshot status is what its events said last: its last ``status`` event, or
  INVALID after a ``cancel`` (halted) or before any event. A leaf below a py_trees
  composite or decorator may also be INVALID where py_trees itself stops finished children
  (a sequence restarting, a decorator stopped), which no event reports.

At the end, each leaf's status in the status file (``status.json``, which ``tree.svg`` is
drawn from) is its last ``status`` event's.
"""

from __future__ import annotations

import textwrap
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import py_trees
import pytest
from interop.scripted import Script, ScriptedLeaf, ScriptState, load_scripted, scripted_registry
from interop.test_btcpp_controls import CASES as BTCPP_CASES
from interop.test_btcpp_controls import GENERIC, tree_file
from interop.test_constructs import CONSTRUCTS, NAV2_RUNS, RUNS
from interop.test_constructs import registry as constructs_registry
from interop.test_nav2_navigators import NAVIGATORS, PALETTE
from interop.test_nav2_ticks import GATING, LONG_DRIVE, REDUCED_TREES, SCRIPTS, SPEED, TICK
from py_trees.common import Status

from sar_framework.cli import main
from sar_framework.engine.api import load_spec
from sar_framework.engine.nodes.control_kinds import CONTROL_KINDS
from sar_framework.engine.nodes.controls.base import BtControl, BtDecorator
from sar_framework.engine.nodes.node_kinds import PY_TREES_KINDS, SCRIPT_KINDS
from sar_framework.engine.registry import Registry, discover
from sar_framework.engine.spec import Category
from sar_framework.events.emitter import EventEmitter
from sar_framework.events.event import EventKind
from sar_framework.runner.status_file import StatusFileWriter
from sar_framework.runner.tree_status import STATUS_TOPIC_NAME, TreeStatusPublisher, decode_status
from sar_framework.runner.tree_ticker import create_behaviour_tree, ros_behaviour_tree_class

pytestmark = [pytest.mark.ros, pytest.mark.timeout(900)]
pytest.importorskip("py_trees_ros.trees", reason="py_trees_ros is not installed")

#: Ticks before which the long drives get a new goal (Nav2's goal-reading decorators).
NEW_GOALS = GATING["the controller runs long, new goals before ticks 3 and 7"]
#: Outer safety bound (seconds) on one awaited message or stream; ~1000x what it takes.
OUTER_S = 20.0

#: py_trees' own kinds: alone, and above and below BT.CPP's (0.3 s a tick for timeout).
PY_TREES_CASES: dict[str, tuple[str, Script, int, float]] = {
    "py_trees' memory sequence, retry, repeat, one_shot, timeout": ("""
        sequence:
          memory: true
          children:
            - retry: {num_failures: 3, child: {Tick: {name: Flaky}}}
            - repeat: {num_success: 2, child: {Tick: {name: Twice}}}
            - one_shot: {policy: on_completion, child: {Tick: {name: Once}}}
            - timeout: {duration: 1.0, child: {Tick: {name: Slow}}}
        """, {"Flaky": ["FAILURE", "RUNNING", "SUCCESS"], "Twice": ["RUNNING", "SUCCESS"],
              "Slow": ["RUNNING"]}, 14, 0.3),
    "py_trees' selector, parallel and status converters": ("""
        selector:
          memory: false
          children:
            - inverter: {child: {Tick: {name: Inv}}}
            - condition: {status: failure, child: {Tick: {name: Awaited}}}
            - parallel:
                policy: success_on_all
                synchronise: false
                children:
                  - count: {child: {Tick: {name: Counted}}}
                  - pass_through: {child: {Tick: {name: Passed}}}
                  - failure_is_success: {child: {Tick: {name: FailOk}}}
                  - running_is_success: {child: {Tick: {name: RunOk}}}
            - sequence:
                memory: false
                children:
                  - success_is_running: {child: {Tick: {name: Busy}}}
            - failure_is_running: {child: {Tick: {name: Wait}}}
        """, {"Inv": ["SUCCESS", "SUCCESS", "FAILURE", "SUCCESS"],
              "Awaited": ["RUNNING", "SUCCESS", "FAILURE", "SUCCESS"],
              "Counted": ["RUNNING", "SUCCESS"], "FailOk": ["FAILURE"], "RunOk": ["RUNNING"],
              "Passed": ["RUNNING", "FAILURE", "SUCCESS"], "Busy": ["SUCCESS", "FAILURE"],
              "Wait": ["FAILURE", "SUCCESS"]}, 10, 0),
    "py_trees' parallels and success_is_failure, running_is_failure": ("""
        parallel:
          policy: success_on_selected
          selected: [Chosen]
          children:
            - success_is_failure: {name: Chosen, child: {Tick: {name: Flip}}}
            - parallel:
                policy: success_on_one
                children:
                  - running_is_failure: {child: {Tick: {name: Never}}}
                  - Tick: {name: One}
        """, {"Flip": ["RUNNING", "FAILURE", "RUNNING", "FAILURE"], "Never": ["RUNNING"],
              "One": ["RUNNING", "SUCCESS"]}, 8, 0),
    "BT.CPP's kinds below and above py_trees' own": ("""
        sequence:
          memory: false
          children:
            - SequenceWithMemory:
                children:
                  - ForceSuccess: {child: {Tick: {name: Try}}}
                  - Repeat: {num_cycles: 2, child: {Tick: {name: Step}}}
                  - selector:
                      memory: true
                      children:
                        - Tick: {name: First}
                        - retry: {num_failures: 2, child: {Tick: {name: Second}}}
            - ReactiveFallback:
                children:
                  - Tick: {name: Guard}
                  - one_shot: {policy: on_successful_completion,
                               child: {Tick: {name: Latched}}}
        """, {"Try": ["FAILURE", "SUCCESS"], "Step": ["RUNNING", "SUCCESS"],
              "First": ["FAILURE", "RUNNING", "FAILURE"], "Second": ["FAILURE", "SUCCESS"],
              "Guard": ["FAILURE", "FAILURE", "SUCCESS", "FAILURE"],
              "Latched": ["RUNNING", "SUCCESS"]}, 16, 0),
}


@dataclass
class Case:
    """One tree ticked with one script."""

    tree: Path
    registry: Registry
    script: Script
    ticks: int
    all_ticks: bool = True
    tick_seconds: float = 0.0
    speed: float | None = None
    goal_ticks: tuple[int, ...] = ()


def _written(folder: Path, name: str, root: str) -> Path:
    folder = folder / name.replace(" ", "_").replace("'", "").replace(",", "")
    folder.mkdir(parents=True, exist_ok=True)
    return tree_file(folder, textwrap.dedent(root))


@pytest.fixture(scope="module")
def cases(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Case]:
    """Every case: its tree written (or imported), its registry, its script and ticks."""
    folder = tmp_path_factory.mktemp("kinds")
    found: dict[str, Case] = {}
    generic = discover([GENERIC], builtins=False, entry_points=False)
    for name, (root, script, ticks, step) in {**BTCPP_CASES, **PY_TREES_CASES}.items():
        found[name] = Case(_written(folder, name, root), generic, script, ticks,
                           tick_seconds=step)
    constructs = constructs_registry()
    for stem, runs in RUNS.items():
        for index, run in enumerate(runs):
            found[f"{stem}-{index}"] = Case(CONSTRUCTS / f"{stem}.yaml", constructs, run.script,
                                            run.ticks, run.all_ticks, run.tick_seconds)
    for index, (script, _expected) in enumerate(NAV2_RUNS):
        found[f"10_nav2_controls-{index}"] = Case(CONSTRUCTS / "10_nav2_controls.yaml",
                                                  constructs, script, 10, False, 0.3)
    nav2 = discover(entry_points=False)
    for xml in NAVIGATORS:
        tree = folder / f"{xml.stem}.yaml"
        assert main(["import", str(xml), "--nodes-model", str(PALETTE), "-o", str(tree)]) == 0
        script = SCRIPTS["the controller fails, the recoveries run"]
        found[f"{xml.stem}-recoveries"] = Case(tree, nav2, script, 10, False, TICK, SPEED)
        if xml.stem in REDUCED_TREES:
            found[f"{xml.stem}-long drive"] = Case(
                tree, nav2, LONG_DRIVE, 12, True, TICK, SPEED, NEW_GOALS)
    return found


CASE_NAMES = ([*BTCPP_CASES, *PY_TREES_CASES]
              + [f"{stem}-{i}" for stem, runs in RUNS.items() for i in range(len(runs))]
              + [f"10_nav2_controls-{i}" for i in range(len(NAV2_RUNS))]
              + [f"{xml.stem}-recoveries" for xml in NAVIGATORS]
              + [f"{stem}-long drive" for stem in REDUCED_TREES])


def test_the_cases_use_every_node_kind(cases: dict[str, Case]) -> None:
    used = {node.kind for case in cases.values()
            for node in load_spec(case.tree, registry=case.registry).nodes()}
    attributes = {attr for case in cases.values()
                  for node in load_spec(case.tree, registry=case.registry).nodes()
                  for attr in node.scripts}
    every = ({kind.key for kind in CONTROL_KINDS} | set(PY_TREES_KINDS)
             | {kind.key for kind in SCRIPT_KINDS})
    assert every - used == set()
    assert {"_failureIf", "_successIf", "_skipIf", "_while", "_onSuccess", "_onFailure",
            "_onHalted", "_post"} - attributes == set()
    assert set(CASE_NAMES) == set(cases)


class Words:
    """What the events said last about each leaf: a ``status`` event's status, or INVALID
    after a ``cancel`` record (the runner emits each record as an event of its ``what``)."""

    def __init__(self, emitter: EventEmitter, writer: StatusFileWriter) -> None:
        self.emitter = emitter
        self.writer = writer
        self.said: dict[str, str] = {}
        self.reported: dict[str, str] = {}
        self._events = 0
        self._records = 0

    def after_tick(self) -> None:
        """Take the tick's events (during the tick) and then its records (after it)."""
        for event in self.emitter.emitted[self._events:]:
            if event.kind == EventKind.STATUS:
                self.said[event.node_uid] = self.reported[event.node_uid] = event.status
        self._events = len(self.emitter.emitted)
        for record in self.writer.failures[self._records:]:
            if record["what"] == EventKind.CANCEL.value:
                self.said[record["uid"]] = Status.INVALID.name
        self._records = len(self.writer.failures)


def _paths(root: py_trees.behaviour.Behaviour) -> dict[int, str]:
    """Each behaviour's path of child indices, as the snapshot feed names them."""
    paths: dict[int, str] = {}
    stack = [(root, "0")]
    while stack:
        behaviour, path = stack.pop()
        paths[id(behaviour)] = path
        stack.extend((child, f"{path}.{i}") for i, child in enumerate(behaviour.children))
    return paths


def _below_py_trees(behaviour: py_trees.behaviour.Behaviour) -> bool:
    """Whether a py_trees composite or decorator (not a BT.CPP one of ours) is above it."""
    parent = behaviour.parent
    while parent is not None:
        if not isinstance(parent, BtControl | BtDecorator):
            return True
        parent = parent.parent
    return False


@pytest.fixture
def ros() -> Iterator[tuple[Any, Any]]:
    """A context with an executor; each case adds its runner and watcher nodes."""
    import rclpy
    from rclpy.context import Context
    from rclpy.executors import SingleThreadedExecutor

    context = Context()
    rclpy.init(context=context)
    executor = SingleThreadedExecutor(context=context)
    try:
        yield context, executor
    finally:
        executor.shutdown()
        rclpy.shutdown(context=context)


@pytest.mark.parametrize("name", CASE_NAMES)
def test_tip_snapshot_status_and_events_agree(name: str, cases: dict[str, Case],
                                              ros: tuple[Any, Any]) -> None:
    from rclpy.node import Node
    from sar_testing.spin import spin_until
    from std_msgs.msg import String

    from sar_framework.watch.snapshot_source import SnapshotFeed

    assert ros_behaviour_tree_class() is not None
    case = cases[name]
    context, executor = ros
    registry = scripted_registry(case.registry)
    loaded, clock = load_scripted(case.tree, registry, tick_seconds=case.tick_seconds,
                                  speed=case.speed)
    state = ScriptedLeaf.state = ScriptState(case.script)
    namespace = f"/kind{CASE_NAMES.index(name)}"
    runner = Node("runner", namespace=namespace, context=context)
    watcher = Node("watcher", namespace=namespace, context=context)
    executor.add_node(runner)
    executor.add_node(watcher)
    kinds = {node.uid: node.kind for node in loaded.spec.nodes()}
    emitter = EventEmitter(nodes={uid: (b, kinds[uid]) for uid, b in loaded.behaviours.items()})
    writer = StatusFileWriter(str(case.tree), loaded.spec, loaded.behaviours, clock,
                              completion="forever", emitter=emitter)
    tree = create_behaviour_tree(loaded.root)  # the runner's order: its handlers first
    tree.visitors.append(writer)
    tree.add_post_tick_handler(writer.after_tick)
    TreeStatusPublisher(runner, loaded.spec, loaded.behaviours).attach(tree)
    documents: dict[int, dict[str, Any]] = {}

    def take(message: String) -> None:
        document = decode_status(message.data)
        documents[document["tick"]] = document

    watcher.create_subscription(String, f"{namespace}/{STATUS_TOPIC_NAME}", take, 100)
    try:
        tree.setup(node=runner, timeout=OUTER_S, events=emitter)
        feed = SnapshotFeed(watcher, f"{namespace}/{STATUS_TOPIC_NAME}")
        assert spin_until(executor, lambda: bool(feed.topic), OUTER_S,
                          step=lambda: feed.poll(time.monotonic() + 1.0)), \
            f"no snapshot stream opened on {namespace}/runner"
        words = Words(emitter, writer)
        paths = _paths(loaded.root)
        leaves = {node.uid: loaded.behaviours[node.uid] for node in loaded.spec.nodes()
                  if node.category == Category.LEAF}
        for tick in range(1, case.ticks + 1):
            if tick in case.goal_ticks:
                py_trees.blackboard.Blackboard.set("/goal", f"goal {tick}")
            tree.tick()
            clock.advance()
            words.after_tick()
            where = f"{name}, tick {tick}\n{chr(10).join(state.lines)}"
            assert loaded.root.tip() is not None, f"the root has no tip: {where}"
            tipless = [b.name for b in loaded.root.iterate()
                       if b.status != Status.INVALID and b.tip() is None]
            assert tipless == [], f"no tip below {tipless}: {where}"
            assert spin_until(executor, lambda t=tick: feed.has(t) and t in documents,
                              OUTER_S), (f"awaited the snapshot and status of tick {tick}; "
                                         f"snapshots {sorted(feed.snapshots)}, statuses "
                                         f"{sorted(documents)}: {where}")
            shown = {n["uid"]: n["status"] for n in feed.snapshots[tick]["nodes"]}
            published = {n["uid"]: n["status"] for n in documents[tick]["nodes"]}
            assert [shown[paths[id(b)]] for b in loaded.behaviours.values()] == \
                [published[uid] for uid in loaded.behaviours], where
            for uid, leaf in leaves.items():
                status, said = shown[paths[id(leaf)]], words.said.get(uid)
                if status != Status.INVALID.name:
                    assert status == said, f"{leaf.name} [{uid}] shows {status}, " \
                        f"its events said {said}: {where}"
                else:
                    assert said in (None, Status.INVALID.name) or _below_py_trees(leaf), \
                        f"{leaf.name} [{uid}] shows INVALID, its events said {said}: {where}"
            if loaded.root.status != Status.RUNNING and not case.all_ticks:
                break
        nodes = writer.document()["nodes"]
        assert {uid: nodes.get(uid) for uid in words.reported} == words.reported, name
        feed.close(executor)
    finally:
        ScriptedLeaf.state = None
        executor.remove_node(watcher)
        watcher.destroy_node()
        executor.remove_node(runner)
        tree.shutdown()  # destroys the runner's node
