"""Property-based fuzzing of scripts: any text gives a script or a ScriptError, never a crash."""

from __future__ import annotations

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from sar_framework.engine.scripting import ScriptError, compile_script

from ..script_variables import DictVariables

_SETTINGS = settings(max_examples=400, deadline=None,
                     suppress_health_check=[HealthCheck.too_slow])
_TOKENS = ["a", "b", "@c", "RED", "1", "0", "2.5", "0x1F", "'s'", '"t"', "true", "false",
           ":=", "=", "+=", "-=", "*=", "/=", "+", "-", "*", "/", "&", "|", "^", "~", "!",
           "&&", "||", "==", "!=", "<", "<=", ">", ">=", "..", "?", ":", "(", ")", ";", " ",
           "\n", "3foo", "'", "#", "1e400", "9" * 20]
_VALUES = st.one_of(st.integers(-(2**63), 2**63 - 1), st.floats(allow_nan=True),
                    st.booleans(), st.text(max_size=5), st.lists(st.integers(), max_size=2))
_TYPES = st.sampled_from(["int", "float", "bool", "str", "object", "list", "pkg/msg/T"])


def _valid(error: ScriptError) -> None:
    assert error.line >= 1 and error.column >= 1
    assert error.message and "\n" not in error.message


@_SETTINGS
@given(st.lists(st.sampled_from(_TOKENS), max_size=25),
       st.dictionaries(st.sampled_from(["a", "b", "@c"]), _VALUES),
       st.dictionaries(st.sampled_from(["a", "b", "@c"]), _TYPES))
def test_token_soup_compiles_runs_and_checks_or_says_why(
        tokens: list[str], values: dict[str, object], types: dict[str, str]) -> None:
    text = " ".join(tokens)
    try:
        script = compile_script(text, enums={"RED": 1})
    except ScriptError as error:
        _valid(error)
        return
    for problem in script.check(types, closed=False, condition=True):
        _valid(problem)
    try:
        script.run(DictVariables(values))
    except ScriptError as error:
        _valid(error)


@_SETTINGS
@given(st.text(max_size=40))
def test_any_text_compiles_or_says_why(text: str) -> None:
    try:
        compile_script(text)
    except ScriptError as error:
        _valid(error)
