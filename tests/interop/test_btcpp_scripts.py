"""Our script language against BehaviorTree.CPP 4.7.3's own script engine, case by case.

Each case is a few scripts run in turn on one fresh blackboard (so later scripts see the
variables earlier ones made), with the enums RED=1, BLUE=3, GREEN=5. Both sides report
each script's outcome the same way: ``NUM <value>``, ``STR <text>``, ``PARSE_ERROR``
(BT.CPP's ParseScript fails; our compile_script raises) or ``RUN_ERROR``. True and False
are the numbers 1 and 0 (BT.CPP gives 1.0/0.0). ``DIFFERENT`` lists the cases
docs/reference/scripts.md names as deliberate differences, with each side's outcome.
"""

from __future__ import annotations

import math
import subprocess
from pathlib import Path

import pytest

from sar_framework.engine.scripting import ScriptError, compile_script

ENUMS = {"RED": 1, "BLUE": 3, "GREEN": 5}

SAME = """
628 | -628 | +5 | 0x100 | 0X1f | 3.14 | -3.14 | 3.14e2 | 3.14e-2 | 3e2 | 3E-2 | 'hi there ' | "dq"
true | false | RED | GREEN | 0xFFFFFFFFFFFFFFFF | 99999999999999999999
0X100g | 0X100. | 3foo | 65. | 65.43foo | 1..2 | 0x | .5 | 'abc | 'it''s' | @@a := 1 | a.b := 1
+x | +-1 | -+1 | --5 | - -5 | !!1 | !true | ~5 | ~2.5 | !0.5 | !2

1 + 2 | 7 - 10 | 6 * 7 | 5 / 2 | 1.5 + 1 | true + 1 | -(1 + 2) | 'a' + 'b' | 1 / 0 | -1 / 0
5 & 3 | 5 | 3 | 5 ^ 3 | 4.0 | 1 | 7 & 2.5 | 1 & 2 | 4 | 1 | 2 & 4 | 1 ^ 3 | 4 | !1 & 1
'x' .. 'y' .. 'z' | 'a' .. 2.5 | 'a' .. true | 'x' .. 3 | 2 .. 'x'
1 && 1 | 1 && 0 | 0 || 0 | 2.0 || 0 | 0.5 && 1 | 2 && 1 | -1 && 1 | 1 == 1 && 2 | 1 && 2 == 2
1 || 0 && 0 | 0 && 1 || 1 | 'abc' && 1
1 < 2 | 2 <= 2 | 3 > 4 | 4 >= 5 | 1 == 1 | 1 != 1 | 'hello' < 'world' | 'b' < 'a'
'3' == 3 | 'true' == 1 | 'RED' == RED | 'BLUE' == 3 | 'a' < 1 | 1 < 'b' | 0.1 + 0.2 == 0.3
1 == 1.0000001 | 1 == 1.001 | 1 < 2 < 3 | 3 > 2 > 1 | 1 < 2 == 1
1 ? 'T' : 'F' | 0 ? 'T' : 'F' | 0.5 ? 5 : 6 | 2 ? 5 : 6 | '1' ? 5 : 6 | '' ? 1 : 2 | 'a' ? 1 : 2
1 ? 2 : 0 ? 3 : 4 | 1 ? 2 : 3 + 4 | (1 ? 2 : 3) + 4 | 1 + 2 ? 5 : 6

10 - 3 * 2 | 2 + 3 * 4 - 1 | (1 + 2) * 3 | -2 * 3 | 1 - -1 | -1 * -1 | !2 == 0
1 + 2 & 3 | 1 + 2 .. 'a' | 'a' .. 1 + 2 | -1 & 1 | ~1 + 1 | 'x' .. -1
x := 1; -x & 1 | x := 1; !x + 1 | x := 1; x + 1 == 'a' .. 'b' | x := 1; x == -1 | x := 1; x != -1

A:=1; | A:=1;;B:=2 | ;A:=1 | A:=1 ; B:=2 ; | a:=1\\nb:=2 | a:=1\\n;b:=2 | (1 +\\n 2) | 1 +\\n 2
1 2 | a b | 1) | (1 | 1 + | a := b := 1 | A:=5;\\nB:=6

x:= 3; y:=5; x+y | x+=1 | x -= 1 | x*=2 | -x | x/=2 | x | y/2 | y & x | y ^ 5.1
A:='hello'; B:=' '; C:='world'; A+B+C | A= '   right' | A | x=A | x='msg' | A=1.0
x < y | y == x ? 'T' : 'F' | v1:= true; v2:= false | v2 = !false | v2 = !v2
v1 && v2 | v1 || v2 | par1:='3'; par2:=3; par1==par2

A:=RED; B:=RED; C:=BLUE | A==B | A!=C | A | C | D := GREEN * 2

y := 2 | y = 2.5 | y | y = '7' | y | y = 'abc' | s := 'str' | s = 1 | s += 'x' | s | s += 1
s -= 'x' | q += 1 | u | n := 5; n /= 2 | n | m := 5.0; m /= 2 | m | k := 5.0; k = 3
A := (B := 2) | B | A ? C := 7 : 2 | C | (A) := 1 | A | A == B == 2 | @r := 4 | @r + 1
"""

DIFFERENT = [
    # (scripts, BT.CPP 4.7.3's outcomes, ours): docs/reference/scripts.md, "Differences from BT.CPP"
    ("5 - 2 + 1 | 10 - 3 - 2 | 12 / 3 * 2", "NUM 2 | NUM 9 | NUM 2", "NUM 4 | NUM 5 | NUM 8"),
    ("'n' .. (1 + 1) | x := -5; 'x' .. x", "STR n2.000000 | STR x-5.000000", "STR n2 | STR x-5"),
    ("b := true | b = 5", "NUM 1 | NUM 5", "NUM 1 | RUN_ERROR"),
    ("x := 1 > 2 | x = 2", "NUM 0 | NUM 2", "NUM 0 | RUN_ERROR"),
    ("'3abc' == 3", "NUM 1", "RUN_ERROR"),
    ("1 .. 2", "EMPTY", "RUN_ERROR"),
    ("trueval := 3", "PARSE_ERROR", "NUM 3"),
    ("3 := 2 | RED := 5", "RUN_ERROR | NUM 5", "PARSE_ERROR | PARSE_ERROR"),
    ("z = 1 | new_var=69", "RUN_ERROR | RUN_ERROR", "NUM 1 | NUM 69"),
]


def cases(table: str) -> list[list[str]]:
    """Each paragraph of ``table`` is a case; ' | ' separates scripts, a line ends one."""
    found: list[list[str]] = []
    for paragraph in table.strip().split("\n\n"):
        scripts = [part.strip() for line in paragraph.splitlines() for part in line.split(" | ")]
        found.append([s.replace("\\n", "\n") for s in scripts])
    return found


class _Vars(dict):
    def get(self, name: str) -> object:  # type: ignore[override]
        return self[name]

    def set(self, name: str, value: object) -> None:
        self[name] = value

    def unset(self, name: str) -> None:
        self.pop(name, None)


def ours(scripts: list[str]) -> list[str]:
    variables, outcomes = _Vars(), []
    for text in scripts:
        try:
            script = compile_script(text, enums=ENUMS)
        except ScriptError:
            outcomes.append("PARSE_ERROR")
            continue
        try:
            value = script.run(variables)
        except ScriptError:
            outcomes.append("RUN_ERROR")
            continue
        outcomes.append(f"STR {value}" if isinstance(value, str) else f"NUM {float(value)!r}")
    return outcomes


def btcpp(oracle: Path, scripts: list[str]) -> list[str]:
    lines = ["#reset", *(f"#enum {name} {value}" for name, value in ENUMS.items())]
    lines += [text.replace("\n", "\\n") for text in scripts]
    done = subprocess.run([str(oracle)], input="\n".join(lines) + "\n", capture_output=True,
                          text=True, check=True, timeout=60)
    return done.stdout.splitlines()


def same(a: str, b: str) -> bool:
    if a.startswith("NUM ") and b.startswith("NUM "):
        x, y = float(a[4:]), float(b[4:])
        return x == y or (math.isnan(x) and math.isnan(y))
    return a == b


@pytest.mark.parametrize("scripts", cases(SAME), ids=lambda s: s[0][:30])
def test_scripts_give_what_btcpp_gives(scripts: list[str], btcpp_script_oracle: Path) -> None:
    theirs = btcpp(btcpp_script_oracle, scripts)
    mine = ours(scripts)
    assert len(theirs) == len(scripts)
    differ = [f"{s!r}: BT.CPP {t}, ours {m}" for s, t, m in zip(scripts, theirs, mine,
                                                                   strict=True)
              if not same(t, m)]
    assert differ == []


@pytest.mark.parametrize(("scripts", "theirs", "mine"), DIFFERENT, ids=lambda s: s[:30])
def test_the_documented_differences(scripts: str, theirs: str, mine: str,
                                    btcpp_script_oracle: Path) -> None:
    texts = scripts.split(" | ")
    expected_theirs, expected_mine = theirs.split(" | "), mine.split(" | ")
    got_theirs, got_mine = btcpp(btcpp_script_oracle, texts), ours(texts)
    assert all(same(a, b) for a, b in zip(got_theirs, expected_theirs, strict=True)), got_theirs
    assert all(same(a, b) for a, b in zip(got_mine, expected_mine, strict=True)), got_mine
