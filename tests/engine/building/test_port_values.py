"""Ports at run time: PortValues on py_trees' blackboard, initial values, LoadedTree.entries."""

from __future__ import annotations

from pathlib import Path

import py_trees
import pytest

from sar_framework.engine.api import load_tree
from sar_framework.engine.building.port_values import PortValues
from sar_framework.engine.ports import InputPort, OutputPort, PortBinding
from sar_framework.engine.registry import Registry

from ..conftest import write
from ..port_setup import PLAN_AND_FOLLOW, clean_blackboard, port_registry  # noqa: F401 (pytest fixtures)

Blackboard = py_trees.blackboard.Blackboard
Status = py_trees.common.Status


def test_plan_into_path_then_follow_it(tree_dir: Path, registry: Registry) -> None:
    tree = load_tree(write(tree_dir, "tree.yaml", PLAN_AND_FOLLOW), registry=registry)
    assert tree.entries == {"goal": "/goal", "start": "/start", "path": "/path",
                            "steps": "/steps"}
    assert Blackboard.get("/steps") == 0  # the initial value, before the first tick
    Blackboard.set("/start", (0, 0))  # the caller's inputs, as Nav2's navigator sets {goal}
    Blackboard.set("/goal", (3, 1))
    statuses, poses = [], []
    for _ in range(3):
        tree.root.tick_once()
        statuses.append(tree.root.status)
        poses.append(Blackboard.get("/start"))
    assert Blackboard.get("/path") == [(1, 1), (2, 1), (3, 1)]
    assert statuses == [Status.RUNNING, Status.RUNNING, Status.SUCCESS]
    assert poses == [(1, 1), (2, 1), (3, 1)] and Blackboard.get("/steps") == 3


def test_subtree_scopes_are_separate_keys(tree_dir: Path, registry: Registry) -> None:
    tree = load_tree(write(tree_dir, "tree.yaml", """
        format: 1
        root:
          sequence:
            memory: true
            children:
              - subtree: Counter
              - subtree: {tree: Counter, ports: {number: 9}}
        subtrees:
          Counter:
            ports:
              number: {type: int, default: 4}
            blackboard:
              out: {type: int}
            root:
              sequence:
                memory: true
                children:
                  - Emit: {value: "{out}", number: "{number}"}
                  - Gauge: {value: "{out}", seen: "{@last}"}
    """), registry=registry)
    assert tree.entries == {"Counter@0_0/number": "/Counter@0_0/number",
                            "Counter@0_1/number": "/Counter@0_1/number",
                            "Counter@0_0/out": "/Counter@0_0/out",
                            "Counter@0_1/out": "/Counter@0_1/out", "last": "/last"}
    tree.root.tick_once()
    assert tree.root.status is Status.SUCCESS
    assert Blackboard.get("/Counter@0_0/out") == 4 and Blackboard.get("/Counter@0_1/out") == 9
    assert Blackboard.get("/last") == 9


def test_literals_and_defaults_reach_the_leaf(tree_dir: Path, registry: Registry) -> None:
    tree = load_tree(write(tree_dir, "tree.yaml", """
        format: 1
        root:
          Say: {text: 3, times: "4", items: "a;b"}
    """), registry=registry)
    tree.root.tick_once()
    assert tree.root.heard == {"text": "3", "times": 4, "rate": 1.0, "loud": False,
                               "items": ["a", "b"], "anything": None}


def test_port_values_on_the_blackboard() -> None:
    count, seen, spare = InputPort("count", int), OutputPort("seen", int), OutputPort("spare")
    ports = PortValues("leaf", {"count": PortBinding(count, key="/n"),
                                "seen": PortBinding(seen, key="/s"), "spare": PortBinding(spare)})
    with pytest.raises(KeyError, match="port 'count' of leaf: entry '/n' has no value"):
        ports.get("count")
    assert "count" not in ports and ports.key("count") == "/n"
    Blackboard.set("/n", "12")  # a string in the entry converts, as BT.CPP does
    assert ports.get("count") == 12 and "count" in ports
    ports.set("seen", 5)
    assert Blackboard.get("/s") == 5
    ports.set("spare", 1)  # an unbound output: the value is dropped
    with pytest.raises(KeyError, match="'count' is not an output port"):
        ports.set("count", 1)
    with pytest.raises(KeyError, match="port 'spare' is not bound"):
        ports.get("spare")
    with pytest.raises(KeyError, match="port 'other' is not a port of this leaf"):
        ports.get("other")


def test_unbound_output_is_dropped(tree_dir: Path, registry: Registry) -> None:
    tree = load_tree(write(tree_dir, "tree.yaml", "format: 1\nroot: {Emit: {}}\n"),
                     registry=registry)
    tree.root.tick_once()
    assert tree.root.status is Status.SUCCESS and tree.entries == {}


def test_activity_stream_sees_port_access() -> None:
    value = InputPort("value", int)
    out = OutputPort("out", int)
    ports = PortValues("Leaf", {"value": PortBinding(value, key="/v"),
                                "out": PortBinding(out, key="/o")})
    Blackboard.enable_activity_stream(100)
    try:
        ports.set("out", 3)
        Blackboard.set("/v", 2)
        assert ports.get("value") == 2
        stream = Blackboard.activity_stream
        assert stream is not None
        seen = [(item.client_name, item.key, item.activity_type) for item in stream.data]
    finally:
        Blackboard.disable_activity_stream()
    assert ("Leaf", "/o", "INITIALISED") in seen and ("Leaf", "/v", "READ") in seen


def test_subtree_names_make_safe_keys(tree_dir: Path, registry: Registry) -> None:
    tree = load_tree(write(tree_dir, "tree.yaml", """
        format: 1
        root: {subtree: "count.v2 x"}
        subtrees:
          "count.v2 x": {Emit: {value: "{out}"}}
    """), registry=registry)
    assert tree.entries == {"count_v2_x@0/out": "/count_v2_x@0/out"}
    tree.root.tick_once()
    assert Blackboard.get("/count_v2_x@0/out") == 7
