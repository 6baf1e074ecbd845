"""Nav2's decorators' blackboard attributes are ports: typed, scoped, checked, exported.

``goal``/``goals`` (GoalUpdatedController, SpeedController), ``path``
(PathLongerOnApproach), ``input_goal``/``output_goal`` (GoalUpdater), typed as
``nav2_tree_nodes.xml`` types them; an unbound ``goal``/``goals`` reads the root's entry
of that name, as Nav2's ``getInputOrBlackboard``.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from engine.conftest import load_problems
from engine.port_setup import (
    clean_blackboard,  # noqa: F401 (pytest fixtures)
    write_tree,
)
from py_trees.blackboard import Blackboard
from py_trees.common import Status
from sar_plugins.nav2.decorators import GoalUpdatedController

from sar_framework.engine.api import load_spec, load_tree
from sar_framework.engine.ports import Direction
from sar_framework.engine.registry import Registry
from sar_framework.interop.btcpp_export import export_btcpp

POSE, PATH = "geometry_msgs/msg/PoseStamped", "nav_msgs/msg/Path"


def test_the_entry_attributes_are_ports_typed_as_nav2s_palette(registry: Registry) -> None:
    ports = {(spec.name, a.name): a.port for spec in registry.kind_plugins()
             for a in spec.kind.attrs if a.port is not None}
    for kind in ("GoalUpdatedController", "SpeedController"):
        assert ports[(kind, "goal")].type == POSE and ports[(kind, "goal")].optional
        assert ports[(kind, "goals")].type == "list" and not ports[(kind, "goals")].required
    assert ports[("PathLongerOnApproach", "path")].type == PATH
    assert ports[("PathLongerOnApproach", "path")].required
    assert ports[("GoalUpdater", "input_goal")].direction is Direction.INPUT
    assert ports[("GoalUpdater", "output_goal")].direction is Direction.OUTPUT
    assert ports[("GoalUpdater", "output_goal")].type == POSE


SCOPED = f"""\
blackboard:
  target: {{type: {POSE}}}
root:
  subtree: {{tree: Watch, ports: {{aim: "{{target}}"}}}}
subtrees:
  Watch:
    ports:
      aim: {{type: {POSE}}}
    root:
      PipelineSequence:
        children:
          - GoalUpdatedController:
              goal: "{{aim}}"
              child: {{Fixed: {{name: Child, status: success}}}}
          - Fixed: {{name: Follow, status: running}}
"""


def test_a_bound_goal_resolves_in_the_subtree_scope_goals_reads_the_root(
        tmp_path: Path, registry: Registry) -> None:
    loaded = load_tree(write_tree(tmp_path, SCOPED), {}, registry=registry)
    node = next(n for n in loaded.spec.nodes() if n.kind == "GoalUpdatedController")
    assert node.bindings["goal"].key == "/target"  # remapped through the insertion
    Blackboard.storage["/target"] = "A"
    watch = next(b for b in loaded.root.iterate() if isinstance(b, GoalUpdatedController))
    statuses = []
    for change in ({}, {}, {"/target": "B"}, {}, {"/goals": ["B", "C"]}):
        Blackboard.storage.update(change)
        loaded.root.tick_once()
        statuses.append(watch.status)
    # starting counts as an update; then the child only on a change of goal or goals
    assert statuses == [Status.SUCCESS, Status.RUNNING, Status.SUCCESS, Status.RUNNING,
                        Status.SUCCESS]


@pytest.mark.parametrize(("text", "message"), [
    (f"blackboard:\n  goal: {{type: {POSE}}}\nroot:\n  PathLongerOnApproach:\n"
     "    path: '{goal}'\n    child: {Fixed: {}}\n",
     f"port 'path' of PathLongerOnApproach reads 'goal' as {PATH}, declared {POSE}"),
    (f"blackboard:\n  goal: {{type: {POSE}}}\nroot:\n  GoalUpdater:\n"
     "    input_goal: '{goal}'\n    output_goal: updated\n    child: {Fixed: {}}\n",
     "output port 'output_goal' must be bound to an entry ('{key}'), got 'updated'"),
    ("root:\n  PathLongerOnApproach: {path: '{plan}', child: {Fixed: {}}}\n",
     "port 'path' of PathLongerOnApproach reads 'plan', but nothing writes it"),
])
def test_the_ports_feed_the_entry_checks(tmp_path: Path, registry: Registry, text: str,
                                         message: str) -> None:
    assert message in load_problems(write_tree(tmp_path, text), registry)


def test_the_export_declares_their_ports_in_the_nav2_models(tmp_path: Path,
                                                            registry: Registry) -> None:
    tree = write_tree(tmp_path, f"blackboard:\n  goal: {{type: {POSE}}}\n"
                      f"  updated: {{type: {POSE}}}\n"
                      "root:\n  GoalUpdater:\n    input_goal: '{goal}'\n"
                      "    output_goal: '{updated}'\n    child: {Fixed: {}}\n")
    xml = export_btcpp(load_spec(tree, registry=registry), registry)
    assert '<GoalUpdater name="GoalUpdater" input_goal="{goal}" output_goal="{updated}">' in xml
    model = xml.split('<Decorator ID="GoalUpdater">')[1].split("</Decorator>")[0]
    assert '<input_port name="input_goal" type="geometry_msgs::msg::PoseStamped">' in model
    assert '<output_port name="output_goal" type="geometry_msgs::msg::PoseStamped">' in model
