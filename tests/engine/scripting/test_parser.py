"""Bad scripts: every syntax error is a ScriptError with a message and a 1-based column."""

from __future__ import annotations

import subprocess
import sys

import pytest

from sar_framework.engine.scripting import ScriptError, compile_script


def error_of(text: str) -> ScriptError:
    with pytest.raises(ScriptError) as caught:
        compile_script(text, enums={"RED": 1})
    return caught.value


@pytest.mark.parametrize(("text", "message", "column"), [
    ("", "empty script", 1),
    ("   \n ", "empty script", 1),
    ("A:=1;", "nothing after the last ';'", 5),
    ("A:=1 ; B:=2 ;", "nothing after the last ';'", 13),
    ("A:=1;;B:=2", "unexpected ';' (an expression must come before each ';')", 6),
    (";A:=1", "unexpected ';'", 1),
    ("1 2", "unexpected '2' (is an operator or a ';' missing before it?)", 3),
    ("a b", "unexpected 'b'", 3),
    ("a:=1\nb:=2", "unexpected 'b'", 1),
    ("1)", "unexpected ')'", 2),
    ("(1", "the script ends in the middle of an expression", 3),
    ("1 +", "the script ends in the middle of an expression", 4),
    ("'abc", "unterminated string", 1),
    ("x := 'it''s'", "unexpected \"'s'\"", 10),
    (".5", "unexpected character '.'", 1),
    ("a.b := 1", "unexpected character '.'", 2),
    ("@@a := 1", "unexpected character '@'", 1),
    ("a # b", "unexpected character '#'", 3),
    ("+x", "unexpected '+'", 1),
    ("1 ? 2 : 0 ? 3 : 4", "'?:' cannot be chained", 11),
    ("a := b := 1", "assignments cannot be chained", 8),
    ("3 := 2", "the left side of ':=' must be a variable", 3),
    ("a + 1 = 2", "the left side of '=' must be a variable", 7),
    ("(a + 1) += 2", "the left side of '+=' must be a variable", 9),
    ("RED := 5", "'RED' is an enum name and cannot be assigned", 1),
])
def test_syntax_errors(text: str, message: str, column: int) -> None:
    error = error_of(text)
    assert message in error.message
    assert error.column == column
    assert error.script == text


def test_an_error_on_a_later_line_has_its_line_and_column() -> None:
    error = error_of("a := 1;\nb := 2;\n  c := (1 +;")
    assert (error.line, error.column) == (3, 12)


@pytest.mark.parametrize(("text", "column", "mixed"), [
    # BT.CPP: "operator cannot be mixed with previous operators", at the same column
    ("1 + 2 & 3", 7, "'&' (bitwise) cannot be mixed with '+' (arithmetic)"),
    ("1 + 2 .. 'a'", 7, "'..' (concatenation) cannot be mixed with '+' (arithmetic)"),
    ("'a' .. 1 + 2", 10, "'+' (arithmetic) cannot be mixed with '..' (concatenation)"),
    ("-1 & 1", 4, "'&' (bitwise) cannot be mixed with '-' (arithmetic)"),
    ("~1 + 1", 4, "'+' (arithmetic) cannot be mixed with '~' (bitwise)"),
    ("!x + 1", 4, "'+' (arithmetic) cannot be mixed with '!' (bitwise)"),
    ("'x' .. -1", 8, "'-' (arithmetic) cannot be mixed with '..'"),
    ("'x' .. !x", 8, "'!' (bitwise) cannot be mixed with '..'"),
    ("x + 1 == 'a' .. 'b'", 14, "'..' (concatenation) cannot be mixed with '+'"),
    ("a := b | c + 1", 12, "'+' (arithmetic) cannot be mixed with '|' (bitwise)"),
])
def test_operator_groups_cannot_be_mixed_without_parentheses(
        text: str, column: int, mixed: str) -> None:
    error = error_of(text)
    assert mixed in error.message
    assert "without parentheses" in error.message
    assert error.column == column


@pytest.mark.parametrize("text", [
    "1 + (2 & 3)", "'x' .. (1 + 2)", "(x + 1) == 'a' .. 'b'", "x == -1", "-x * 2",
    "!a == b", "!a && b + 1 > 2", "x + 1 ? a & 1 : 'a' .. 'b'", "(~x) + 1",
])
def test_groups_may_meet_across_parentheses_comparisons_and_logic(text: str) -> None:
    compile_script(text)


def test_whitespace_newlines_and_escaped_newlines_are_blanks() -> None:
    assert compile_script("a := 1 +\\\n 2;\n\tb := a").writes == ("a", "b")


def test_lark_is_imported_only_when_a_script_is_compiled() -> None:
    code = ("import sys, sar_framework.engine.nodes.script_nodes; a = 'lark' in sys.modules; "
            "from sar_framework.engine.scripting import compile_script; compile_script('1'); "
            "print(a, 'lark' in sys.modules)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True, timeout=60)
    assert done.stdout.split() == ["False", "True"]
