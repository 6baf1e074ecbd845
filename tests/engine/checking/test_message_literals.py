"""Literals of message-typed ports in tree files: checked before the run, at the wrong field."""

from __future__ import annotations

from collections.abc import Callable

import pytest

from sar_framework.engine.checking.validate import ValidationResult
from sar_framework.engine.message_literals import MessageLiteral

from ..conftest import Checker
from ..port_setup import port_registry  # noqa: F401 (pytest fixture)

TREE = """
format: 1
blackboard:
  start: {type: geometry_msgs/msg/Point, initial: "0;0;0"}
  home: {type: geometry_msgs/msg/PoseStamped, initial: {x: 1.0, y: 2.0, yaw: 0.0}}
  path: {type: nav_msgs/msg/Path}
root:
  Plan: {goal: GOAL, start: "{start}", path: "{path}"}
"""

# Message literals are read from the installed ROS interfaces' .msg files: not in the
# engine's py_trees-only environment (.venv-compat), where ROS tests are skipped.
pytestmark = pytest.mark.ros


def test_a_literal_of_the_fields_or_text_binds_a_message_port(
    validate: Callable[..., ValidationResult],
) -> None:
    for goal in ("{x: 3, y: 4.5}", '"3;4.5;0"'):
        result = validate(TREE.replace("GOAL", goal))
        assert result.ok, [str(d) for d in result.diagnostics]
        assert result.spec is not None
        plan = next(n for n in result.spec.nodes() if n.name == "Plan")
        value = plan.bindings["goal"].value
        assert isinstance(value, MessageLiteral) and value.type == "geometry_msgs/msg/Point"
        assert value.fields["y"] == 4.5
        home = result.spec.entries["/home"].initial
        assert home.fields["header"] == {"frame_id": "map", "stamp": "now"}
        assert home.fields["pose"]["position"] == {"x": 1.0, "y": 2.0, "z": 0.0}


def test_a_wrong_field_is_reported_where_it_stands(check: Checker) -> None:
    tree = TREE.replace("GOAL", "{x: 3, yy: 4.5, z: up}").replace(
        "yaw: 0.0}", "yew: 0.0}").replace('"0;0;0"', '"0;0"')
    assert check(tree) == [
        "tree.yaml:3:51: error: initial value of 'start': '0;0' is not a "
        "geometry_msgs/msg/Point: expected 'x;y;z', or bind an entry ('{key}')",
        "tree.yaml:4:73: error: initial value of 'home': yew: not a key of the pose shorthand "
        "of geometry_msgs/msg/PoseStamped (did you mean 'yaw'?) (keys: x, y, z, yaw, "
        "frame_id)",
        "tree.yaml:7:23: error: port 'goal': yy: not a field of geometry_msgs/msg/Point (did "
        "you mean 'y'?) (fields: x, y, z)",
        "tree.yaml:7:35: error: port 'goal': z: expected a float64, got 'up'",
    ]


def test_nested_fields_are_located_too(check: Checker) -> None:
    tree = TREE.replace(
        "{type: geometry_msgs/msg/PoseStamped, initial: {x: 1.0, y: 2.0, yaw: 0.0}}",
        "\n    type: geometry_msgs/msg/PoseStamped\n    initial:\n      pose:\n"
        "        postion: {x: 1}").replace("GOAL", "{x: 1}")
    assert check(tree) == [
        "tree.yaml:8:9: error: initial value of 'home': pose.postion: not a field of "
        "geometry_msgs/msg/Pose (did you mean 'position'?) (fields: position, orientation)",
    ]


def test_a_message_port_takes_no_number(check: Checker) -> None:
    assert check(TREE.replace("GOAL", "3")) == [
        "tree.yaml:7:16: error: port 'goal' must be bound to a mapping literal, or an entry "
        "('{key}'), got integer 3",
    ]
