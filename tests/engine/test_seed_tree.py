"""The reference mission tree from YAML equals the same tree built by hand in py_trees."""

from __future__ import annotations

from typing import Any

import py_trees

from sar_framework import load_spec, load_tree
from sar_framework.engine.registry import Registry
from sar_framework.engine.spec import Category

from .conftest import FIXTURES

SEED = FIXTURES / "search_and_rescue.yaml"


def hand_built(registry: Registry, zone_manager: object) -> py_trees.behaviour.Behaviour:
    """The tree of docs/mission-spec.md, written directly in py_trees."""

    def cls(name: str) -> Any:
        spec = registry.get(name)
        assert spec is not None
        return spec.cls

    zm = {"zone_manager": zone_manager}
    detect = cls("DetectSurvivor")(name="DetectSurvivor", service="/detect_survivor", **zm)
    broadcast = cls("BroadcastSurvivorTF")(name="BroadcastSurvivorTF", detector=detect, **zm)
    found = py_trees.composites.Sequence("SurvivorFound", memory=True, children=[
        cls("IsSurvivorDetected")(name="IsSurvivorDetected?", detector=detect),
        broadcast,
        cls("NotifyBase")(name="NotifyBase", detector=detect, broadcaster=broadcast),
    ])
    handle = py_trees.composites.Selector("HandleDetection", memory=False, children=[
        found, cls("LogNoDetection")(name="LogNoDetection", **zm),
    ])
    patrol = py_trees.composites.Sequence("Patrol", memory=True, children=[
        cls("ZonesRemaining")(name="ZonesRemaining?", **zm),
        cls("NavigateToZone")(name="NavigateToZone", timeout_s=120.0, **zm),
        detect,
        handle,
        cls("AdvanceZone")(name="AdvanceZone", **zm),
    ])
    home = py_trees.decorators.OneShot(
        name="NavigateToBaseOneShot",
        child=cls("NavigateToBase")(name="NavigateToBase", timeout_s=120.0, **zm),
        policy=py_trees.common.OneShotPolicy.ON_COMPLETION,
    )
    return py_trees.composites.Selector("MissionOrReturnToBase", memory=False,
                                        children=[patrol, home])


def _index(root: py_trees.behaviour.Behaviour) -> dict[int, str]:
    return {id(b): str(i) for i, b in enumerate(root.iterate())}


def assert_same_tree(a: py_trees.behaviour.Behaviour, b: py_trees.behaviour.Behaviour) -> None:
    """Compare two trees node for node, references by position in the tree."""
    pos_a, pos_b = _index(a), _index(b)
    nodes_a, nodes_b = list(a.iterate()), list(b.iterate())
    assert len(nodes_a) == len(nodes_b)
    for x, y in zip(nodes_a, nodes_b, strict=True):
        assert type(x) is type(y), (x.name, y.name)
        assert x.name == y.name
        assert [c.name for c in x.children] == [c.name for c in y.children]
        assert getattr(x, "memory", None) == getattr(y, "memory", None)
        assert getattr(x, "policy", None) == getattr(y, "policy", None)
        kw_x, kw_y = getattr(x, "kwargs", {}), getattr(y, "kwargs", {})
        assert kw_x.keys() == kw_y.keys(), x.name
        for key, value in kw_x.items():
            other = kw_y[key]
            if isinstance(value, py_trees.behaviour.Behaviour):
                assert pos_a[id(value)] == pos_b[id(other)], (x.name, key)
            else:
                assert value == other, (x.name, key)


def test_seed_tree_equals_hand_built(registry: Registry) -> None:
    zone_manager = object()
    loaded = load_tree(SEED, context={"zone_manager": zone_manager}, registry=registry)
    expected = hand_built(registry, zone_manager)
    assert_same_tree(loaded.root, expected)
    # The memory flags and the OneShot policy, spelled out.
    root = loaded.root
    assert isinstance(root, py_trees.composites.Selector) and root.memory is False
    patrol, home = root.children
    assert isinstance(patrol, py_trees.composites.Sequence) and patrol.memory is True
    assert isinstance(home, py_trees.decorators.OneShot)
    assert home.policy == py_trees.common.OneShotPolicy.ON_COMPLETION
    # Reference wiring: all three readers hold the one DetectSurvivor instance.
    detect = patrol.children[2]
    readers = patrol.children[3].children[0].children
    assert all(r.kwargs["detector"] is detect for r in readers)
    assert readers[2].kwargs["broadcaster"] is readers[1]
    assert all(b.kwargs.get("zone_manager", zone_manager) is zone_manager for b in root.iterate()
               if hasattr(b, "kwargs"))


def test_behaviours_map_and_uids(registry: Registry) -> None:
    loaded = load_tree(SEED, context={"zone_manager": object()}, registry=registry)
    spec_nodes = list(loaded.spec.nodes())
    assert len(loaded.behaviours) == len(spec_nodes) == 14
    for node in spec_nodes:
        assert loaded.behaviours[node.uid].name == node.name
    assert loaded.behaviours["0"] is loaded.root
    assert loaded.behaviours["0.0.3"].name == "HandleDetection"
    handle = next(n for n in spec_nodes if n.name == "HandleDetection")
    assert handle.subtree == "handle_detection"
    assert handle.location.file.endswith("handling.yaml")


def test_spec_shape(registry: Registry) -> None:
    spec = load_spec(SEED, registry=registry)
    assert spec.name == "search_and_rescue"
    assert spec.root.kind == "selector" and spec.root.attrs == {"memory": False}
    leaves = [n for n in spec.nodes() if n.category is Category.LEAF]
    assert [n.kind for n in leaves] == [
        "ZonesRemaining", "NavigateToZone", "DetectSurvivor", "IsSurvivorDetected",
        "BroadcastSurvivorTF", "NotifyBase", "LogNoDetection", "AdvanceZone", "NavigateToBase",
    ]
    notify = leaves[5]
    assert notify.refs["detector"] is leaves[2]
    assert notify.refs["broadcaster"] is leaves[4]
    assert notify.attrs == {"detector": "detect", "broadcaster": "broadcast"}
    assert leaves[1].attrs == {"timeout_s": 120.0}


def test_loaded_tree_ticks_to_success(registry: Registry) -> None:
    loaded = load_tree(SEED, context={"zone_manager": object()}, registry=registry)
    loaded.root.tick_once()
    assert loaded.root.status == py_trees.common.Status.SUCCESS
