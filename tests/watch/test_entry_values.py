"""The entries' encoding for the status topic: safe bounded text, changes only, folding."""

from __future__ import annotations

import json

import py_trees
import pytest

from sar_framework.runner.entry_values import (
    TEXT_MAX,
    UNSET,
    EntryTracker,
    apply_entries,
    type_text,
    value_text,
    writers_of,
)


@pytest.fixture(autouse=True)
def clean_blackboard():
    py_trees.blackboard.Blackboard.clear()
    yield
    py_trees.blackboard.Blackboard.clear()


def test_scalars_read_as_python_writes_them() -> None:
    assert [value_text(v) for v in (1, 2.5, True, None, "north")] == \
        ["1", "2.5", "True", "None", "'north'"]
    assert value_text(1 / 3) == "0.333333"
    assert [type_text(v) for v in (1, 2.5, "a", None)] == ["int", "float", "str", "NoneType"]


def test_long_values_are_bounded() -> None:
    assert len(value_text("x" * 10_000)) == TEXT_MAX
    assert value_text("x" * 10_000).endswith("…")
    text = value_text(list(range(1000)))
    assert text == "[0, 1, 2, 3, … (1000 items)]"
    assert value_text({"a": 1, "b": [1, 2]}) == "{'a': 1, 'b': [1, 2]}"
    deep: list = []
    for _ in range(50):
        deep = [deep]
    assert value_text(deep) == "[[[…]]]"


def test_unknown_objects_are_never_repr_d() -> None:
    class Loud:
        def __repr__(self) -> str:
            raise AssertionError("repr called")

    assert value_text(Loud()) == "<Loud>"


def test_a_value_whose_fields_raise_is_unprintable_not_an_error() -> None:
    class Broken:
        @classmethod
        def get_fields_and_field_types(cls) -> dict[str, str]:
            return {"x": "double"}

        @property
        def x(self) -> float:
            raise RuntimeError("boom")

    assert value_text(Broken()) == "<Broken: unprintable>"


def test_ros_messages_are_compact() -> None:
    geometry = pytest.importorskip("geometry_msgs.msg")
    pose = geometry.PoseStamped()
    pose.header.frame_id = "map"
    pose.pose.position.x = 1.5
    assert type_text(pose) == "geometry_msgs/msg/PoseStamped"
    text = value_text(pose)
    assert text == ("PoseStamped@map(pose=(position=(x=1.5, y=0, z=0), "
                    "orientation=(x=0, y=0, z=0, w=1)))")
    path = pytest.importorskip("nav_msgs.msg").Path()
    path.poses = [pose] * 500
    assert value_text(path) == ("Path@(poses=[@map(pose=…), @map(pose=…), @map(pose=…), "
                                "@map(pose=…), … (500 items)])")
    covariance = geometry.PoseWithCovariance()  # a numeric array field
    assert value_text(covariance.covariance) == "[0, 0, 0, 0, … (36 items)]"
    assert value_text(geometry.Point(x=1.0, y=0.5)) == "Point(x=1, y=0.5, z=0)"


def test_a_message_literal_reads_as_its_type_and_fields() -> None:
    from sar_framework.engine.message_literals import message_literal

    literal = message_literal("geometry_msgs/msg/Point", "1;2;3")
    assert value_text(literal) == "Point{'x': 1, 'y': 2, 'z': 3}"
    assert type_text(literal) == "geometry_msgs/msg/Point"


def test_the_tracker_returns_changes_only_and_everything_on_request() -> None:
    board = py_trees.blackboard.Client(name="Writer")
    board.register_key("count", access=py_trees.common.Access.WRITE)
    board.register_key("/sub/path", access=py_trees.common.Access.WRITE)
    assert writers_of(["/count", "/sub/path", "/nobody"]) == {"/count": "Writer",
                                                              "/sub/path": "Writer"}
    tracker = EntryTracker({"count": "/count", "sub/path": "/sub/path"},
                           {"/count": "Writer"})
    assert tracker.changes() == [["count", "/count", UNSET, "unset", "Writer"],
                                 ["sub/path", "/sub/path", UNSET, "unset", ""]]
    assert tracker.changes() == []
    board.count = 1
    assert tracker.changes() == [["count", "/count", "1", "int", "Writer"]]
    board.count = 1
    assert tracker.changes() == []
    board.set("/sub/path", [(0, 0), (1, 1)])
    assert tracker.changes() == [["sub/path", "/sub/path", "[(0, 0), (1, 1)]", "list", ""]]
    assert len(tracker.changes(full=True)) == 2
    assert tracker.final()["count"] == {"key": "/count", "value": "1", "type": "int",
                                        "writer": "Writer"}
    json.dumps(tracker.changes(full=True))  # the rows go into a JSON document


def test_a_tree_without_entries_costs_nothing() -> None:
    tracker = EntryTracker({})
    assert len(tracker) == 0 and tracker.changes(full=True) == [] and tracker.final() == {}


def test_folding_keeps_the_last_value_of_each_entry() -> None:
    first = apply_entries({}, [["b", "/b", "1", "int", "W"], ["a", "/a", "-", "unset", ""]],
                          full=True)
    assert list(first) == ["a", "b"]
    later = apply_entries(first, [["b", "/b", "2", "int", "W"]])
    assert later["b"]["value"] == "2" and later["a"]["value"] == "-"
    assert first["b"]["value"] == "1"  # not changed in place
    assert apply_entries(later, [["a", "/a", "3", "int", ""]], full=True) == {
        "a": {"name": "a", "key": "/a", "value": "3", "type": "int", "writer": ""}}
