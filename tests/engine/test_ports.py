"""Port declarations: type names, literal conversion (BT.CPP's rules), compatibility."""

from __future__ import annotations

import py_trees
import pytest

from sar_framework.engine.plugin import Param, leaf
from sar_framework.engine.ports import (
    NO_DEFAULT,
    BidirectionalPort,
    Direction,
    EntryRef,
    InputPort,
    Naming,
    OutputPort,
    compatible,
    convert,
    entry_ref,
    type_name,
)


def test_type_names() -> None:
    assert [type_name(t) for t in (str, int, float, bool, list, object)] == [
        "str", "int", "float", "bool", "list", "any"]
    assert type_name("nav_msgs/msg/Path") == "nav_msgs/msg/Path"
    for bad in (dict, "Path", "nav_msgs/Path", "double"):
        with pytest.raises(TypeError, match="unsupported port type"):
            type_name(bad)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("type_", "literal", "value"),
    [
        ("int", 3, 3), ("int", "-12", -12), ("int", 4.0, 4),
        ("float", 2, 2.0), ("float", "1.5", 1.5), ("float", "1e3", 1000.0),
        ("bool", True, True), ("bool", "TRUE", True), ("bool", "0", False),
        ("bool", "False", False), ("bool", 1, True),
        ("str", "a", "a"), ("str", 3, "3"), ("str", False, "false"),
        ("list", "a;b;c", ["a", "b", "c"]), ("list", [1, 2], [1, 2]), ("list", "", []),
        ("any", {"x": 1}, {"x": 1}),
    ],
)
def test_convert(type_: str, literal: object, value: object) -> None:
    got = convert(type_, literal)
    assert got == value and type(got) is type(value)


@pytest.mark.parametrize(
    ("type_", "literal", "message"),
    [
        ("int", "12abc", "expected an int, got '12abc'"),
        ("int", 1.5, "expected an int, got 1.5"),
        ("int", True, "expected an int, got boolean true"),
        ("float", "fast", "expected a float, got 'fast'"),
        ("bool", "yes", "expected a bool (true/false/1/0), got 'yes'"),
        ("str", None, "expected a str, got null"),
        pytest.param("nav_msgs/msg/Path", "x", "a nav_msgs/msg/Path has no text form",
                     marks=pytest.mark.ros),  # read from the ROS interfaces' .msg files
    ],
)
def test_convert_refuses(type_: str, literal: object, message: str) -> None:
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        convert(type_, literal)


def test_compatibility() -> None:
    assert compatible("int", "float") and not compatible("float", "int")
    assert compatible("any", "nav_msgs/msg/Path") and compatible("str", "any")
    assert not compatible("nav_msgs/msg/Path", "geometry_msgs/msg/PoseStamped")


def test_entry_refs() -> None:
    assert entry_ref("{goal}") == EntryRef("goal")
    assert entry_ref("{@goal}") == EntryRef("goal", root=True)
    assert entry_ref("{=}", "path") == EntryRef("path")
    assert entry_ref("goal") is None and entry_ref(3) is None and entry_ref("{a}b") is None
    assert str(EntryRef("g", root=True)) == "{@g}"


def test_port_declarations() -> None:
    goal = InputPort("goal", "geometry_msgs/msg/PoseStamped", description="Where.")
    assert goal.direction is Direction.INPUT and goal.default is NO_DEFAULT and goal.required
    assert InputPort("hz", float, default="2").default == 2.0
    path = OutputPort("path", "nav_msgs/msg/Path")
    assert path.direction.writes and not path.direction.reads and not path.required
    both = BidirectionalPort("count", int, default="{count}")
    assert both.direction.reads and both.direction.writes and both.default == "{count}"


def test_an_optional_input_still_reads_a_value() -> None:
    timeout = InputPort("server_timeout", int, optional=True)
    assert timeout.optional and not timeout.required
    assert timeout.naming is Naming.VALUE  # optional is not read as the naming field
    assert not InputPort("goal").optional and InputPort("goal").naming is Naming.VALUE


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda: InputPort("hz", float, default="fast"), "default expected a float"),
        (lambda: OutputPort("path", default="literal"), "an output's default must be an entry"),
        (lambda: InputPort("a.b"), "not a valid entry name"),
        (lambda: InputPort("x", default="{a.b}"), "bad default entry"),
        (lambda: InputPort("x", dict), "unsupported port type"),  # type: ignore[arg-type]
    ],
)
def test_bad_port_declarations(make: object, message: str) -> None:
    with pytest.raises(TypeError, match=message):
        make()  # type: ignore[operator]


def test_leaf_records_ports() -> None:
    @leaf(params=[Param("label", str, default="x")], ports=[InputPort("goal", int)])
    class Uses(py_trees.behaviour.Behaviour):
        """Uses a port."""

    spec = Uses.__sar_plugin__  # type: ignore[attr-defined]
    assert spec.ports == (InputPort("goal", int),)
    assert spec.port("goal") is spec.ports[0] and spec.port("label") is None


@pytest.mark.parametrize(
    ("params", "ports", "message"),
    [
        ([Param("goal", str, default="")], [InputPort("goal")], "port name 'goal'"),
        ([], [InputPort("ports")], "port name 'ports'"),
        ([], [InputPort("a"), OutputPort("a")], "port name 'a'"),
        ([], ["goal"], "'goal' is not a Param or a Port"),
    ],
)
def test_leaf_refuses_bad_ports(params: list, ports: list, message: str) -> None:
    with pytest.raises(TypeError, match=message):

        @leaf(params=params, ports=ports)
        class Bad(py_trees.behaviour.Behaviour):
            """Bad."""
