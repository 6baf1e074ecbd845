"""The one parameter declaration: its rule for a value, its range text, what a leaf may use."""

from __future__ import annotations

import math

import py_trees
import pytest

from sar_framework.engine import plugin
from sar_framework.engine.param import REQUIRED, Param, type_name


def test_the_plugin_param_is_the_project_param() -> None:
    assert plugin.Param is Param and plugin.REQUIRED is REQUIRED


@pytest.mark.parametrize(("param", "value", "problem"), [
    (Param("rate", float, 2.0, exclusive_minimum=0.0), 0, "must be > 0, got 0"),
    (Param("rate", float, 2.0, exclusive_minimum=0.0), -2.0, "must be > 0, got -2.0"),
    (Param("rate", float, 2.0, exclusive_minimum=0.0), 3, None),  # an integer is a number
    (Param("rate", float, 2.0), True, "must be a number, got True"),
    (Param("rate", float, 2.0), math.nan, "must be finite, got nan"),
    (Param("rate", float, 2.0), "fast", "must be a number, got 'fast'"),
    (Param("n", int, 1, minimum=1, maximum=3), 4, "must be >= 1 and <= 3, got 4"),
    (Param("n", int, 1), 1.5, "must be an integer, got 1.5"),
    (Param("on", bool, False), "maybe", "must be true or false, got 'maybe'"),
    (Param("mode", str, "auto", enum=("auto", "once")), "onse",
     "must be one of auto, once, got 'onse' (did you mean 'once'?)"),
    (Param("ids", list[str], None), ["a", 1], "must be a list of strings, got ['a', 1]"),
    (Param("ids", list[str], None), "a", "must be a list of strings, got 'a'"),
    (Param("nums", list[int], None), [1, 2], None),
    (Param("nums", list[int], None), [True], "must be a list of integers, got [True]"),
    (Param("path", str | list[str], ""), ["a", "b"], None),
    (Param("path", str | list[str], ""), "a:b", None),
    (Param("path", str | list[str], ""), 3, "must be a string or a list of strings, got 3"),
])
def test_one_rule_for_a_value(param: Param, value: object, problem: str | None) -> None:
    assert param.problem(value) == problem


def test_bounds_and_type_names() -> None:
    assert Param("s", float, 1.0, exclusive_minimum=0.0, maximum=1000.0).bounds() == \
        "> 0 and <= 1000"
    assert Param("s", float, 0.0, minimum=0.0).bounds() == ">= 0"
    assert Param("s", float, 0.0).bounds() == ""
    assert [type_name(t) for t in (float, list[int], str | list[str])] == [
        "float", "list[int]", "str | list[str]"]


def test_a_default_that_breaks_its_own_rule_is_a_declaration_error() -> None:
    with pytest.raises(TypeError, match=r"default 0\.0 must be > 0"):
        Param("rate", float, 0.0, exclusive_minimum=0.0)
    with pytest.raises(TypeError, match="unsupported type"):
        Param("x", dict, None)


def test_a_leaf_param_is_a_scalar() -> None:
    with pytest.raises(TypeError, match="a leaf param is a str, int, float or bool"):
        @plugin.leaf(params=[Param("zones", list[str], None)])
        class Leaf(py_trees.behaviour.Behaviour):
            pass
