"""CompiledScript.check: static type problems against declared types, with their columns."""

from __future__ import annotations

import pytest

from sar_framework.engine.scripting import compile_script

from ..script_variables import DictVariables

TYPES = {
    "i": "int", "f": "float", "b": "bool", "s": "str", "o": "object", "l": "list",
    "pose": "geometry_msgs/msg/PoseStamped", "pose2": "geometry_msgs/msg/PoseStamped",
    "@goal": "geometry_msgs/msg/PoseStamped", "@count": "int",
}


def problems(text: str, types: dict[str, str] | None = None, **options: bool) -> list[str]:
    script = compile_script(text, enums={"RED": 1})
    return [f"{p.column}: {p.message}" for p in script.check(TYPES if types is None else types,
                                                              **options)]


@pytest.mark.parametrize("text", [
    "i + 1", "f * i / 2", "b && i > 2", "s + 'x'", "s .. i", "i .. s", "s == 'x'",
    "s < i", "i = 3", "i = 3.0", "f = i", "b = true", "b = i > 1", "i = '5'", "i = RED",
    "i += 1", "f -= 0.5", "s += 'x'", "s = s .. 'x'", "o + 1", "o = 'x'", "i = o", "pose = pose2",
    "pose = o", "pose2 = @goal", "@count += 1", "new := 3; new + 1", "new := 's'; new .. 1",
    "i ? s : f", "l = l", "x := pose; pose2 = x", "~i | 1", "!b", "-f", "i = b ? 1 : 2",
])
def test_well_typed_scripts_have_no_problems(text: str) -> None:
    assert problems(text) == []


@pytest.mark.parametrize(("text", "problem"), [
    ("'a' + 1", "5: '+' does not apply to a str and an int"),
    ("s - 'x'", "3: '-' does not apply to a str and a str"),
    ("s * 2", "3: '*' does not apply to a str and an int"),
    ("i = s", "1: cannot assign a str to 'i', which is an int"),
    ("i = 'x'", "5: the string 'x' is not a number (assigned to 'i', an int)"),
    ("s = 1", "1: cannot assign an int to 's', which is a str"),
    ("i = 2.5", "1: cannot assign a float to 'i', which is an int"),
    ("b = 0.5", "1: cannot assign a float to 'b', which is a bool"),
    ("pose = i", "1: cannot assign an int to 'pose', which is a "
                 "geometry_msgs/msg/PoseStamped"),
    ("pose = l", "1: cannot assign a list to 'pose', which is a "
                 "geometry_msgs/msg/PoseStamped"),
    ("pose + 1", "6: '+' does not apply to a geometry_msgs/msg/PoseStamped and an int"),
    ("pose == pose2", "6: cannot compare a geometry_msgs/msg/PoseStamped with a "
                      "geometry_msgs/msg/PoseStamped"),
    ("l < 1", "3: cannot compare a list with an int"),
    ("i < 'abc'", "5: the string 'abc' is not a number"),
    ("-s", "1: prefix '-' does not apply to a str"),
    ("!l", "1: prefix '!' does not apply to a list"),
    ("s && b", "3: '&&' does not apply to a str and a bool"),
    ("i & s", "3: '&' does not apply to an int and a str"),
    ("i .. f", "3: '..' needs a string on one side, not two numbers"),
    ("s += 1", "1: '+=' does not apply to 's' (a str) and an int"),
    ("i -= 'x'", "1: '-=' does not apply to 'i' (an int) and a str"),
    ("l += 1", "1: '+=' does not apply to 'l' (a list) and an int"),
    ("pose ? 1 : 2", "6: a geometry_msgs/msg/PoseStamped cannot be the condition of '?:'"),
    ("new := 's'; new = 1", "13: cannot assign an int to 'new', which is a str"),
    ("@goal + 1", "7: '+' does not apply to a geometry_msgs/msg/PoseStamped and an int"),
])
def test_type_problems(text: str, problem: str) -> None:
    assert problems(text) == [problem]


def test_unknown_variables_in_a_closed_set() -> None:
    assert problems("x + 1") == ["1: unknown variable 'x'"]
    assert problems("x = 1") == ["1: unknown variable 'x' (use ':=' to create it)"]
    assert problems("x += 1") == ["1: unknown variable 'x'"]
    assert problems("@other") == ["1: unknown variable '@other'"]
    assert problems("x := 1; x + 1") == []  # := creates
    assert problems("x + 1; x := 1") == ["1: unknown variable 'x'"]  # ...from there on


def test_an_open_set_accepts_unknown_variables_as_any_type() -> None:
    assert problems("x + 1; y = 'a' .. x; z += 1", closed=False) == []
    assert problems("x + 1; s = 1", closed=False) == ["8: cannot assign an int to 's', "
                                                      "which is a str"]


def test_every_problem_is_reported_in_script_order() -> None:
    assert problems("a := s + 1; i = 'x' .. 2; pose < 1") == [
        "8: '+' does not apply to a str and an int",
        "13: cannot assign a str to 'i', which is an int",
        "32: cannot compare a geometry_msgs/msg/PoseStamped with an int",
    ]


def test_problems_name_the_script() -> None:
    (problem,) = compile_script("s + 1").check({"s": "str"})
    assert problem.script == "s + 1"
    assert str(problem) == "'+' does not apply to a str and an int (column 3) in script 's + 1'"


def test_a_condition_must_give_a_number_or_a_boolean() -> None:
    assert problems("i > 1", condition=True) == []
    assert problems("b", condition=True) == []
    assert problems("o", condition=True) == []
    assert problems("s", condition=True) == ["1: a condition must give a number or "
                                             "true/false, not a str"]
    assert problems("i := 1; pose", condition=True) == [
        "9: a condition must give a number or true/false, not a geometry_msgs/msg/PoseStamped"]


def test_the_check_uses_the_types_the_values_have_at_run_time() -> None:
    # What the check infers for an expression is what running it gives.
    v = DictVariables(i=2, f=0.5, b=True, s="x")
    for text, inferred in [("i + 1", int), ("i * f", float), ("i / 1", float), ("b && 1", bool),
                           ("i < f", bool), ("s .. i", str), ("~f", int), ("-b", int)]:
        assert type(compile_script(text).run(v)) is inferred, text
        assert problems(text) == []
