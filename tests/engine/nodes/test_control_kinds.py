"""BT.CPP's blackboard nodes through the ports machinery: scopes, checks, schema, edges.

Switch's ``variable``, SetBlackboard's ``value``/``output_key``, UnsetBlackboard's ``key``,
the ``entry`` of SkipUnlessUpdated/WaitValueUpdate/WasEntryUpdated and the Loops'
``queue``/``value`` are ports (``control_kinds``): they resolve in the node's scope like a
leaf's ports and feed the same entry checks. Also: pre/post-conditions on BT.CPP's
control nodes, built.
"""

from __future__ import annotations

from pathlib import Path

import py_trees
import pytest
from py_trees.common import Status

from sar_framework.engine.api import load_spec, load_tree
from sar_framework.engine.checking.schema import tree_schema
from sar_framework.engine.nodes.node_kinds import KINDS
from sar_framework.engine.nodes.skipping import was_skipped
from sar_framework.engine.ports import Direction, Naming
from sar_framework.engine.registry import Registry
from sar_framework.engine.rendering.labels import data_edges

from ..conftest import load_problems
from ..port_setup import (
    clean_blackboard,  # noqa: F401 (pytest fixture)
    port_registry,  # noqa: F401 (pytest fixture)
    write_tree,
)

Blackboard = py_trees.blackboard.Blackboard


def _ticked(root: py_trees.behaviour.Behaviour) -> dict[str, Status]:
    """Tick once; return the status of every behaviour ticked, by name (before resets)."""
    return {b.name: b.status for b in root.tick()}


def _problems(tmp_path: Path, registry: Registry, text: str) -> str:
    return load_problems(write_tree(tmp_path, text), registry)


def test_the_attributes_that_use_the_blackboard_are_ports_with_a_direction() -> None:
    ports = {(key, a.name): a.port for key, kind in KINDS.items() for a in kind.attrs
             if a.port is not None}
    assert ports[("Switch3", "variable")].direction is Direction.INPUT
    assert ports[("SetBlackboard", "value")].direction is Direction.INPUT
    assert ports[("SetBlackboard", "output_key")].direction is Direction.OUTPUT
    assert ports[("SetBlackboard", "output_key")].naming is Naming.BARE_NAME
    assert ports[("UnsetBlackboard", "key")].naming is Naming.BARE_NAME
    assert ports[("SkipUnlessUpdated", "entry")].naming is Naming.NAME
    assert ports[("LoopInt", "value")].type == "int"
    assert ports[("LoopInt", "value")].direction is Direction.OUTPUT
    assert ports[("LoopString", "queue")].type == "list"
    assert ports[("Switch3", "case_1")].direction is Direction.INPUT


def test_the_schema_shows_them_as_ports(registry: Registry) -> None:
    defs = tree_schema(registry)["$defs"]
    text = str(defs)
    assert "output port (any): The entry written, by name" in text
    assert "input port (any): The value compared (as text) with the cases" in text
    assert "output port (int): The entry each value is written to" in text


LAYERED = """\
blackboard:
  mode: {type: str, initial: "2"}
  rooted: {type: str}
  copy: {type: str}
root:
  Sequence:
    children:
      - subtree: {tree: Pick, ports: {choice: "{mode}"}}
      - subtree: {tree: Copy, autoremap: true}
      - subtree: Own
subtrees:
  Pick:
    ports:
      choice: {type: str}
    root:
      Switch2:
        variable: "{choice}"
        case_1: "1"
        case_2: "2"
        children: [Fixed: {status: failure}, Fixed: {name: Two, status: success},
                   Fixed: {status: failure}]
  Copy:
    Sequence:
      children:
        - SetBlackboard: {value: "{mode}", output_key: copy}
        - SetBlackboard: {value: "3", output_key: "@rooted"}
  Own:
    Sequence:
      children:
        - SetBlackboard: {value: "{@mode}", output_key: mine}
        - SkipUnlessUpdated: {entry: mine, child: {Fixed: {name: Updated}}}
        - UnsetBlackboard: {key: mine}
"""


def test_control_ports_resolve_in_their_subtree_scope(tmp_path: Path,
                                                      registry: Registry) -> None:
    tree = load_tree(write_tree(tmp_path, LAYERED), {}, registry=registry)
    ticked = _ticked(tree.root)
    assert tree.root.status == Status.SUCCESS
    assert ticked["Updated"] == ticked["Two"] == Status.SUCCESS
    storage = Blackboard.storage
    assert storage["/copy"] == "2"  # autoremapped: the parent's entry
    assert storage["/rooted"] == "3"  # '@rooted': the root's entry
    assert "/Own@0_2/mine" not in storage  # its own scope; unset again
    spec = tree.spec
    bindings = {n.name: n.bindings for n in spec.nodes() if n.bindings}
    assert bindings["Switch2"]["variable"].key == "/mode"  # remapped from 'choice'
    assert bindings["UnsetBlackboard"]["key"].key == "/Own@0_2/mine"


def test_data_edges_include_the_blackboard_nodes(tmp_path: Path, registry: Registry) -> None:
    spec = load_spec(write_tree(tmp_path, LAYERED), registry=registry)
    names = {n.uid: n.name for n in spec.nodes()}
    edges = {(names[w], names[r], key) for w, r, key in data_edges(spec)}
    assert ("SetBlackboard", "SkipUnlessUpdated", "Own@0_2/mine") in edges
    assert ("SetBlackboard", "UnsetBlackboard", "Own@0_2/mine") not in edges  # it writes


@pytest.mark.parametrize(("root", "message"), [
    ("  Switch2:\n    variable: '{nothing}'\n    case_1: a\n    case_2: b\n"
     "    children: [Fixed: {}, Fixed: {}, Fixed: {}]\n",
     "tree.yaml:4:15: error: port 'variable' of Switch2 reads 'nothing', but nothing writes it"),
    ("  SkipUnlessUpdated: {entry: ghost, child: {Fixed: {}}}\n",
     "port 'entry' of SkipUnlessUpdated reads 'ghost', but nothing writes it"),
    ("  SetBlackboard: {value: '1', output_key: '{x}'}\n",
     "tree.yaml:3:43: error: port 'output_key' names its entry without braces: write 'x'"),
    ("  UnsetBlackboard: {key: 'a.b'}\n",
     "port 'key': 'a.b' is not a valid entry name"),
    ("  LoopInt: {queue: '1;2', value: item, child: {Fixed: {}}}\n",
     "output port 'value' must be bound to an entry ('{key}'), got 'item'"),
    ("  LoopInt: {queue: '{items}', value: '{n}', child: {Fixed: {}}}\n"
     "blackboard:\n  items: {type: int, initial: 3}\n  n: {type: str}\n",
     "port 'queue' of LoopInt reads 'items' as list, declared int"),
    ("  LoopInt: {queue: '1;2', value: '{n}', child: {Fixed: {}}}\n"
     "blackboard:\n  n: {type: str}\n",
     "port 'value' of LoopInt writes int to 'n', declared str"),
])
def test_control_ports_feed_the_entry_checks(tmp_path: Path, registry: Registry, root: str,
                                             message: str) -> None:
    assert message in _problems(tmp_path, registry, "root:\n" + root)


def test_an_unknown_entry_of_a_declaring_subtree_has_a_did_you_mean(tmp_path: Path,
                                                                    registry: Registry) -> None:
    text = """\
root:
  subtree: Watch
subtrees:
  Watch:
    blackboard:
      mode: {type: str, initial: a}
    root:
      WaitValueUpdate: {entry: "{mdoe}", child: {Fixed: {}}}
"""
    assert ("port 'entry' of WaitValueUpdate: 'mdoe' is not an entry of subtree 'Watch' "
            "(did you mean 'mode'?)") in _problems(tmp_path, registry, text)


def test_a_leaf_output_port_counts_as_an_update(tmp_path: Path, registry: Registry) -> None:
    text = """\
root:
  Sequence:
    children:
      - Emit: {value: "{x}"}
      - SkipUnlessUpdated: {entry: x, child: {Fixed: {name: Seen}}}
"""
    tree = load_tree(write_tree(tmp_path, text), {}, registry=registry)
    assert _ticked(tree.root).get("Seen") == Status.SUCCESS


CONDITIONS = """\
root:
  Sequence:
    children:
      - SetBlackboard: {value: "1", output_key: flag}
      - SequenceWithMemory:
          _skipIf: "flag == 1"
          children: [Fixed: {name: R1, status: failure}, Fixed: {name: R2}]
      - Parallel:
          _skipIf: "flag == 1"
          children: [Fixed: {name: P1}, Fixed: {name: P2}]
      - Switch2:
          _skipIf: "flag != 1"
          _onSuccess: "done := true"
          variable: "{flag}"
          case_1: "1"
          case_2: "2"
          children: [Fixed: {name: One}, Fixed: {name: Two}, Fixed: {name: Other}]
      - Fallback:
          _failureIf: "flag == 1"
          children: [Fixed: {name: Never}]
"""


def test_pre_and_post_conditions_work_on_bt_cpp_controls(tmp_path: Path,
                                                         registry: Registry) -> None:
    tree = load_tree(write_tree(tmp_path, CONDITIONS), {}, registry=registry)
    skipped = []
    ticked = set()
    for behaviour in tree.root.tick():  # every behaviour ticked, as it finishes its tick
        ticked.add(behaviour.name)
        if behaviour.name in ("SequenceWithMemory", "Parallel", "Switch2"):
            skipped.append((behaviour.name, was_skipped(behaviour)))
    assert tree.root.status == Status.FAILURE  # the Fallback's _failureIf
    assert {"R1", "R2", "P1", "P2", "Two", "Other", "Never"}.isdisjoint(ticked)
    assert {"One", "Switch2"} <= ticked
    assert ("SequenceWithMemory", True) in skipped and ("Parallel", True) in skipped
    assert ("Switch2", True) not in skipped
    assert Blackboard.storage["/done"] is True


def test_a_switch_case_may_read_an_entry(tmp_path: Path, registry: Registry) -> None:
    text = """\
blackboard:
  wanted: {type: str, initial: b}
  unset: {type: str}
  mode: {type: str}
root:
  Sequence:
    children:
      - SetBlackboard: {value: b, output_key: mode}
      - Switch3:
          variable: "{mode}"
          case_1: "{unset}"
          case_2: a
          case_3: "{wanted}"
          children: [Fixed: {name: One}, Fixed: {name: Two}, Fixed: {name: Three},
                     Fixed: {name: Other}]
"""
    tree = load_tree(write_tree(tmp_path, text), {}, registry=registry)
    switch = next(n for n in tree.spec.nodes() if n.kind == "Switch3")
    assert switch.bindings["case_3"].key == "/wanted"
    assert _ticked(tree.root).get("Three") == Status.SUCCESS
    assert "port 'case_1' of Switch2 reads 'nope'" in _problems(
        tmp_path, registry, "root:\n  Switch2:\n    variable: a\n    case_1: '{nope}'\n"
        "    case_2: b\n    children: [Fixed: {}, Fixed: {}, Fixed: {}]\n")


def test_set_blackboard_parses_a_literal_into_its_declared_entry(tmp_path: Path,
                                                                 registry: Registry) -> None:
    text = """\
blackboard:
  n: {type: int}
  s: {type: str, initial: x}
root:
  SetBlackboard: {value: "7", output_key: n}
"""
    tree = load_tree(write_tree(tmp_path, text), {}, registry=registry)
    tree.root.tick_once()
    assert Blackboard.storage["/n"] == 7  # BT.CPP parses it into the typed entry too
    bad = text.replace('value: "7"', "value: seven")
    assert ("tree.yaml:6:26: error: port 'value' of SetBlackboard, written to 'n' (declared "
            "int): expected an int, got 'seven'") in _problems(tmp_path, registry, bad)
    copy = text.replace('value: "7"', 'value: "{s}"')
    assert "SetBlackboard copies 's' (declared str) to 'n' (declared int)" in _problems(
        tmp_path, registry, copy)


@pytest.mark.ros  # a message literal: the .msg files of the ROS interfaces
def test_set_blackboard_writes_a_pose_literal(tmp_path: Path, registry: Registry) -> None:
    text = """\
blackboard:
  goal: {type: geometry_msgs/msg/PoseStamped}
root:
  SetBlackboard: {value: "1.0;2.0;0.0", output_key: goal}
"""
    tree = load_tree(write_tree(tmp_path, text), {}, registry=registry)
    tree.root.tick_once()
    goal = Blackboard.storage["/goal"]
    assert goal.type == "geometry_msgs/msg/PoseStamped"
    assert goal.fields["pose"]["position"] == {"x": 1.0, "y": 2.0, "z": 0.0}
    assert ("tree.yaml:5:26: error: port 'value' of SetBlackboard, written to 'goal' (declared "
            "geometry_msgs/msg/PoseStamped): '1.0;2.0' is not a geometry_msgs/msg/PoseStamped"
            ) in _problems(tmp_path, registry, text.replace("1.0;2.0;0.0", "1.0;2.0"))
