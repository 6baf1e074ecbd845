"""docs/reference/node-kinds.md lists exactly the declared node kinds.

Its tables' first column names every kind the engine declares (py_trees', the script
nodes, BT.CPP's) and every control and decorator the built-in plugins add (Nav2's), and
no kind that is not declared, so a kind added, moved or renamed changes the page too.
"""

from __future__ import annotations

import re
from pathlib import Path

from sar_framework.engine.nodes.node_kinds import KINDS
from sar_framework.engine.registry import default_registry

PAGE = Path(__file__).resolve().parents[2] / "docs" / "reference" / "node-kinds.md"
#: ``Switch2`` .. ``Switch6``: a range of numbered kinds in one cell.
RANGE = re.compile(r"`([A-Za-z]+?)(\d+)` \.\. `\1(\d+)`")


def documented(text: str) -> set[str]:
    """The kinds the page's tables name in their first column (header rows left out)."""
    names: set[str] = set()
    for line in text.splitlines():
        if not line.startswith("| `"):
            continue
        cell = line.split("|")[1]
        for stem, low, high in RANGE.findall(cell):
            names |= {f"{stem}{n}" for n in range(int(low), int(high) + 1)}
        names |= set(re.findall(r"`([A-Za-z_0-9]+)`", RANGE.sub("", cell)))
    return names


def test_the_page_names_every_declared_kind_and_no_other() -> None:
    declared = set(KINDS) | {spec.name for spec in default_registry().kind_plugins()}
    named = documented(PAGE.read_text(encoding="utf-8"))
    assert sorted(declared - named) == [], "declared, not on docs/reference/node-kinds.md"
    assert sorted(named - declared) == [], "on docs/reference/node-kinds.md, not declared"


def test_a_kind_left_out_of_the_page_is_noticed() -> None:
    """The comparison can fail: a page without RecoveryNode's row misses a declared kind."""
    text = "\n".join(line for line in PAGE.read_text(encoding="utf-8").splitlines()
                     if not line.startswith("| `RecoveryNode`"))
    assert "RecoveryNode" not in documented(text)
    assert "Switch4" in documented(text)


def test_the_page_repeats_each_declared_difference_word_for_word() -> None:
    """How a py_trees kind ticks unlike its BT.CPP spelling is written at its declaration."""
    text = PAGE.read_text(encoding="utf-8")
    declared = {kind.key: kind.differences for kind in KINDS.values() if kind.differences}
    assert {"retry", "repeat", "timeout", "parallel", "one_shot"} <= set(declared)
    rows = {key: f"| `{key}` | {text_} |" for key, text_ in declared.items()}
    assert [key for key, row in rows.items() if row not in text] == []
    section = text.split("## py_trees' kinds beside BT.CPP's")[1].split("\n## ")[0]
    listed = re.findall(r"^\| `([a-z_]+)` \|", section, flags=re.MULTILINE)
    assert sorted(listed) == sorted(declared), "a row for a kind that declares no difference"
