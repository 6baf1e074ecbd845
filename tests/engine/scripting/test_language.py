"""The script language: literals, every operator, precedence, values and run-time errors.

Cases marked "BT.CPP" restate BehaviorTree.CPP 4.7.3's own tests
(tests/script_parser_test.cpp) in Python; the rest were checked against the 4.7.3
library's ParseScriptAndExecute, except where docs/reference/scripts.md lists a difference.
"""

from __future__ import annotations

import math

import pytest

from sar_framework.engine.scripting import ScriptError, compile_script

from ..script_variables import DictVariables

COLORS = {"RED": 1, "BLUE": 3, "GREEN": 5}


def run(text: str, variables: DictVariables | None = None, **enums: int) -> object:
    return compile_script(text, enums=enums or COLORS).run(
        DictVariables() if variables is None else variables)


def error_of(text: str, variables: DictVariables | None = None) -> ScriptError:
    with pytest.raises(ScriptError) as caught:
        run(text, variables)
    return caught.value


@pytest.mark.parametrize(("text", "value"), [
    ("628", 628), ("-628", -628), ("+5", 5), ("0x100", 256), ("0X1f", 31),
    ("3.14", 3.14), ("-3.14", -3.14), ("3.14e2", 314.0), ("3.14e-2", 0.0314),
    ("3e2", 300.0), ("3E-2", 0.03), ("'hello world '", "hello world "),
    ('"double"', "double"), ("''", ""), ("true", True), ("false", False),
    ("0x7FFFFFFFFFFFFFFF", 2**63 - 1), ("RED", 1), ("GREEN", 5),
])
def test_literals(text: str, value: object) -> None:
    result = run(text)
    assert result == value
    assert type(result) is type(value)


@pytest.mark.parametrize(("text", "column"), [
    ("0X100g", 1), ("0X100.", 1), ("3foo", 1), ("65.", 1), ("65.43foo", 1), ("1..2", 1),
    ("0x", 1), ("x := 12ab", 6),
])
def test_numbers_with_a_suffix_are_invalid(text: str, column: int) -> None:
    # BT.CPP: AnyTypes_Failing ("invalid suffix on integer literal")
    error = error_of(text)
    assert "invalid number" in error.message
    assert error.column == column


@pytest.mark.parametrize("text", ["0xFFFFFFFFFFFFFFFF", "99999999999999999999", "1e400"])
def test_numbers_out_of_range(text: str) -> None:
    assert "range" in error_of(text).message or "64 bits" in error_of(text).message


@pytest.mark.parametrize(("text", "value"), [
    ("1 + 2", 3), ("7 - 10", -3), ("6 * 7", 42), ("5 / 2", 2.5), ("4 / 2", 2.0),
    ("1.5 + 1", 2.5), ("true + 1", 2), ("-(1 + 2)", -3), ("--5", 5), ("- -5", 5),
    ("-+1", -1), ("'a' + 'b'", "ab"),
    ("5 & 3", 1), ("5 | 3", 7), ("5 ^ 3", 6), ("~5", -6), ("~2.5", -3), ("4.0 | 1", 5),
    ("!true", False), ("!0", True), ("!!1", True), ("!0.5", False), ("!(1 == 2)", True),
    ("'x' .. 'y' .. 'z'", "xyz"), ("'n=' .. 3", "n=3"), ("2 .. 'x'", "2x"),
    ("'a' .. 2.5", "a2.500000"), ("'a' .. true", "a1"), ("'x' .. (1 + 2)", "x3"),
    ("1 && 1", True), ("1 && 0", False), ("0 || 0", False), ("2.0 || 0", True),
    ("0.5 && 1", True),
    ("1 < 2", True), ("2 <= 2", True), ("3 > 4", False), ("4 >= 5", False),
    ("1 == 1", True), ("1 != 1", False), ("'hello' == 'hello'", True),
    ("'hello' != 'world'", True), ("'hello' < 'world'", True), ("'hello' > 'world'", False),
    ("'3' == 3", True), ("3 == '3'", True), ("'true' == 1", True), ("'RED' == RED", True),
    ("'BLUE' == 3", True), ("0.1 + 0.2 == 0.3", True), ("1 == 1.0000001", True),
    ("1 == 1.001", False), ("1 < 2 < 3", True), ("3 > 2 > 1", True), ("1 < 2 == 1", False),
    ("1 ? 'T' : 'F'", "T"), ("0 ? 'T' : 'F'", "F"), ("0.5 ? 5 : 6", 5), ("2 ? 5 : 6", 5),
    ("'1' ? 5 : 6", 5),
])
def test_operators(text: str, value: object) -> None:
    result = run(text)
    assert result == value
    assert type(result) is type(value)


def test_division_by_zero_follows_ieee() -> None:
    assert run("1 / 0") == math.inf
    assert run("-1 / 0") == -math.inf
    assert math.isnan(run("0 / 0"))  # type: ignore[arg-type]


@pytest.mark.parametrize(("text", "value"), [
    # BT.CPP #1029 (fixed after 4.7.3, which read "5 - 2 + 1" as 5 - (2 + 1)): left to right
    ("5 - 2 + 1", 4), ("10 - 3 - 2", 5), ("2 + 3 - 1", 4), ("12 / 3 / 2", 2.0),
    ("12 / 3 * 2", 8.0), ("2 + 3 * 4 - 1", 13), ("(1 + 2) * 3", 9), ("1 + 2 * 3", 7),
    ("-2 * 3", -6), ("1 - -1", 2), ("-1 * -1", 1),
    # & binds tighter than | and ^, which share a level
    ("1 & 2 | 4", 4), ("1 | 2 & 4", 1), ("1 ^ 3 | 4", 6), ("!1 & 1", 0),
    # || and && share one level, left to right (BT.CPP: "1 || 0 && 0" is 0)
    ("1 || 0 && 0", False), ("0 && 1 || 1", True),
    # comparisons bind tighter than logic; ?: looser than both
    ("1 == 1 && 2 == 2", True), ("1 + 2 ? 5 : 6", 5), ("1 ? 2 : 3 + 4", 2),
    ("(1 ? 2 : 3) + 4", 6), ("!2 == 0", True), ("-3 + 1", -2),
])
def test_precedence(text: str, value: object) -> None:
    assert run(text) == value


def test_equations_bt_cpp() -> None:
    # BT.CPP: ParserTest.Equations
    v = DictVariables()
    assert run("x:= 3; y:=5; x+y", v) == 8
    assert v == {"x": 3, "y": 5}
    for text, x in [("x+=1", 4), ("x += 1", 5), ("x-=1", 4), ("x -= 1", 3), ("x*=2", 6)]:
        assert run(text, v) == x
        assert v["x"] == x
    assert run("-x", v) == -6
    assert run("x/=2", v) == 3
    assert v["x"] == 3 and type(v["x"]) is int
    assert (run("y", v), run("y/2", v), run("y*2", v), run("y-x", v)) == (5, 2.5, 10, 2)
    assert (run("y & x", v), run("y | x", v), run("y ^ x", v)) == (5 & 3, 5 | 3, 5 ^ 3)
    with pytest.raises(ScriptError):
        run("y ^ 5.1", v)
    assert run("A:='hello'; B:=' '; C:='world'; A+B+C", v) == "hello world"
    assert run("A= '   right'; B= ' center '; C= 'left    '  ", v) == "left    "
    assert (v["A"], v["B"], v["C"]) == ("   right", " center ", "left    ")
    for text in ["x=A", "x='msg'", "A=1.0"]:  # an entry keeps its type
        with pytest.raises(ScriptError):
            run(text, v)
    for text in [" 'hello' = 'world' ", " 'hello' = 2.0 ", " 3.0 = 2.0 "]:
        with pytest.raises(ScriptError, match="must be a variable"):
            run(text, v)
    assert (run("x < y", v), run("y > x", v), run("y != x", v), run("y == x", v)) == (
        True, True, True, False)
    assert run("y == x ? 'T' : 'F'", v) == "F"
    assert run("y != x ? 'T' : 'F'", v) == "T"
    assert run(" 'true' ", v) == "true"
    run("v1:= true; v2:= false", v)
    assert (v["v1"], v["v2"]) == (True, False)
    assert run(" v2 = true ", v) is True
    assert run(" v2 = !false ", v) is True
    assert run(" v2 = !v2 ", v) is False
    assert (run("v1 && v2", v), run("v1 || v2", v)) == (False, True)
    assert run("(y == x) || (x == 3)", v) is True
    assert run(" y == x  &&  x == 3 ", v) is False
    assert run(" par1:='3'; par2:=3; par1==par2", v) is True
    assert run(" par1:='3'; par2:=4; par1!=par2", v) is True


def test_enums_bt_cpp() -> None:
    # BT.CPP: ParserTest.EnumsBasic and EnumsXML
    v = DictVariables()
    run("A:=RED; B:=RED; C:=BLUE", v)
    assert run("A==B", v) is True
    assert run("A!=C", v) is True
    assert (v["A"], v["C"]) == (1, 3)
    assert compile_script("A := THE_ANSWER", enums={"THE_ANSWER": 42}).run(v) == 42


@pytest.mark.parametrize(("script", "value"), [
    ("A:=0; A!=-1", True), ("A:=-1; A!=-1", False), ("A:=0; A>-1", True), ("A:=0; A<-1", False),
])
def test_compare_with_negative_numbers(script: str, value: bool) -> None:
    # BT.CPP #832 (4.7.3 could refuse "A!=-1"; fixed upstream)
    assert run(script, DictVariables()) is value


def test_statements_run_in_order_and_the_last_value_is_returned() -> None:
    v = DictVariables()
    assert run("a := 1; b := a + 1; c := b * 10; c - 1", v) == 19
    assert v == {"a": 1, "b": 2, "c": 20}
    assert run("A:=5;\nB:=6", v) == 6  # BT.CPP: ParserTest.NewLine
    assert run("(1 +\n 2)") == 3


def test_assignment_is_an_expression() -> None:
    v = DictVariables()
    assert run("A := (B := 2)", v) == 2
    assert v == {"A": 2, "B": 2}
    assert run("A ? C := 7 : 2", v) == 7  # the middle of ?: is a whole expression
    assert v["C"] == 7
    assert run("(A) := 3", v) == 3


def test_only_the_chosen_branch_is_evaluated() -> None:
    v = DictVariables(flag=1)
    assert run("flag ? (a := 1) : (b := 2)", v) == 1
    assert "b" not in v


def test_logic_evaluates_both_sides_as_bt_cpp_does() -> None:
    v = DictVariables()
    assert run("0 && (hit := 1)", v) is False
    assert v["hit"] == 1
    with pytest.raises(ScriptError, match="'unset' has no value"):
        run("0 && unset", v)


def test_a_comparison_chain_stops_at_the_first_false_link() -> None:
    v = DictVariables()
    assert run("2 < 1 < (hit := 5)", v) is False
    assert "hit" not in v


@pytest.mark.parametrize(("start", "text", "value"), [
    (3, "x += 1", 4), (3, "x -= 1", 2), (3, "x *= 2", 6), (6, "x /= 2", 3),
    (1.5, "x += 1", 2.5), (2.0, "x = 3", 3.0), (5, "x = '7'", 7), (5, "x = 4.0", 4),
    ("ab", "x += 'c'", "abc"), ("ab", "x = 'cd'", "cd"), (True, "x = 0", False),
    (False, "x = 1.0", True), (True, "x = 'false'", False), (1, "x = BLUE", 3),
])
def test_an_entry_keeps_its_type(start: object, text: str, value: object) -> None:
    v = DictVariables(x=start)
    run(text, v)
    assert v["x"] == value
    assert type(v["x"]) is type(value)


@pytest.mark.parametrize(("start", "text", "message"), [
    (5, "x = 2.5", "cannot store float 2.5 in 'x', which holds an int"),
    (5, "x /= 2", "cannot store float 2.5"),  # BT.CPP: "n := 5; n /= 2" fails too
    (5, "x *= 1.5", "cannot store float 7.5"),
    (5, "x = 'abc'", "the string 'abc' is not a number"),
    ("s", "x = 1", "cannot store int 1 in 'x', which holds a str"),
    ("s", "x += 1", "'+=' needs numbers"),
    ("s", "x -= 'a'", "'-=' does not apply to strings"),
    (3, "x += 'a'", "'+=' with a string needs a string"),
    (True, "x = 5", "cannot store int 5 in 'x', which holds a bool"),
    ([1], "x = 1", "cannot store int 1 in 'x', which holds a list"),
])
def test_assignment_type_clashes(start: object, text: str, message: str) -> None:
    v = DictVariables(x=start)
    error = error_of(text, v)
    assert message in error.message
    assert error.column == 1
    assert v["x"] == start


def test_an_opaque_value_is_copied_into_its_own_type() -> None:
    v = DictVariables(a=[1, 2], b=[3])
    assert run("b = a", v) == [1, 2]
    assert run("c := a", v) == [1, 2]


def test_reading_an_unset_variable_is_a_run_time_error() -> None:
    # BT.CPP: NotInitializedComparison (an entry that exists but has no value)
    v = DictVariables()
    for text, column in [("x < 0", 1), ("x == 0", 1), ("1 + x", 5), ("x += 1", 1)]:
        error = error_of(text, v)
        assert "'x' has no value" in error.message
        assert error.column == column
        assert error.script == text
    assert not v


@pytest.mark.parametrize(("text", "message", "column"), [
    ("'a' + 1", "'+' does not apply to str 'a' and int 1", 5),
    ("'a' - 'b'", "'-' does not apply to str 'a' and str 'b'", 5),
    ("'x' * 2", "'*' does not apply", 5),
    ("7 & 2.5", "'&' needs integers, not 2.5", 3),
    ("!'a'", "prefix '!' does not apply to a string", 1),
    ("-'a'", "prefix '-' does not apply to a string", 1),
    ("'abc' && 1", "'&&' does not apply to str 'abc' and int 1", 7),
    ("2 && 1", "2 is not a boolean (an integer condition must be 0 or 1)", 3),
    ("1 == 1 && 2", "2 is not a boolean", 8),
    ("1 .. 2", "'..' needs a string and a string or number", 3),
    ("'a' < 1", "the string 'a' is not a number", 5),
    ("'3abc' == 3", "the string '3abc' is not a number", 8),
    ("'' ? 1 : 2", "the string '' is not a number", 4),
    ("x := 1; 'a' < x", "the string 'a' is not a number", 13),
])
def test_run_time_errors(text: str, message: str, column: int) -> None:
    error = error_of(text)
    assert message in error.message
    assert error.column == column
    assert str(error).endswith(f"(column {column}) in script {text!r}")


def test_a_failed_statement_leaves_earlier_ones_done() -> None:
    v = DictVariables()
    error = error_of("a := 1; b := a + 'x'; c := 3", v)
    assert error.column == 16
    assert v == {"a": 1}


def test_errors_on_later_lines_say_the_line() -> None:
    error = error_of("a := 1;\n  b := a + 'x'")
    assert (error.line, error.column) == (2, 10)
    assert "line 2, column 10" in str(error)


def test_root_blackboard_names() -> None:
    v = DictVariables()
    assert run("@goal := 4; @goal + 1", v) == 5
    assert v == {"@goal": 4}
    script = compile_script("@count += 1; local := @count")
    assert script.reads == ("@count",)
    assert script.writes == ("@count", "local")


def test_names() -> None:
    v = DictVariables()
    assert run("trueval := 3; trueval", v) == 3  # a keyword's prefix is a plain name
    assert run("é := 2; é + _x1", DictVariables(_x1=1)) == 3


def test_reads_and_writes() -> None:
    script = compile_script("x := a + RED; y = b ? c : x; z += 1; w := w2", enums=COLORS)
    assert script.reads == ("a", "b", "c", "x", "z", "w2")
    assert script.writes == ("x", "y", "z", "w")
    assert script.text == "x := a + RED; y = b ? c : x; z += 1; w := w2"


def test_integers_past_64_bits_go_on_as_floats() -> None:
    assert run("0x7FFFFFFFFFFFFFFF * 4") == float(2**63 - 1) * 4
    error = error_of("x := 3037000500; x = x * x * x")
    assert "cannot store" in error.message or "64-bit" in error.message
    assert "64-bit integers" in error_of("1e30 | 1").message


def test_absurdly_deep_scripts_are_refused_not_crashed() -> None:
    assert "nested too deeply" in error_of("-" * 5000 + "1").message
    assert run("(" * 100 + "1" + ")" * 100) == 1
