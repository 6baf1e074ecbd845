"""The quick YAML reader gives what PyYAML gives, with the same key positions, or nothing.

``quick_yaml.parse`` returns None for anything outside its subset; whenever it returns a
value, that value must equal ``yaml.safe_load`` (compared by ``repr``, so ``1``, ``1.0``
and ``True`` differ and NaN equals NaN) and every located key must stand where PyYAML's
composer puts it.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from sar_framework.engine import quick_yaml

from .conftest import FIXTURES, REPO, make_registry
from .strategies import documents, mutated_texts
from .test_errors import CASES

_SETTINGS = settings(max_examples=300, deadline=None,
                     suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
REPO_TREES = sorted((REPO / "trees").rglob("*.yaml"))
ALL_YAML = REPO_TREES + sorted(FIXTURES.rglob("*.yaml"))


def plain(value: Any) -> Any:
    """The quick value without positions."""
    if type(value) is tuple:
        return plain(value[0])
    if type(value) is dict:
        return {key: plain(item) for key, item in value.items()}
    if type(value) is list:
        return [plain(item) for item in value]
    return value


def check_positions(quick: Any, node: yaml.Node) -> None:
    """Every mapping-valued key is located where PyYAML's composer put it; nothing else."""
    if isinstance(node, yaml.MappingNode):
        assert type(quick) is dict and len(quick) == len(node.value)
        for key_node, value_node in node.value:
            entry = quick[key_node.value]
            if isinstance(value_node, yaml.MappingNode):
                mark = key_node.start_mark
                assert type(entry) is tuple, key_node.value
                assert entry[1:] == (mark.line + 1, mark.column + 1), key_node.value
                check_positions(entry[0], value_node)
            else:
                assert type(entry) is not tuple
                check_positions(entry, value_node)
    elif isinstance(node, yaml.SequenceNode):
        assert type(quick) is list and len(quick) == len(node.value)
        for item, item_node in zip(quick, node.value, strict=True):
            check_positions(item, item_node)


def same_as_pyyaml(text: str) -> bool:
    """Assert the quick reading equals PyYAML's; return whether the text was in the subset."""
    quick = quick_yaml.parse(text)
    if quick is None:
        return False
    assert repr(plain(quick)) == repr(yaml.safe_load(text))
    check_positions(quick, yaml.compose(text, Loader=yaml.SafeLoader))
    return True


@pytest.mark.parametrize("path", ALL_YAML, ids=[str(p.relative_to(REPO)) for p in ALL_YAML])
def test_repository_files(path: Path) -> None:
    text = path.read_text(encoding="utf-8")
    in_subset = same_as_pyyaml(text)
    if path in REPO_TREES:
        assert in_subset, "every tree the project ships is written in the quick subset"


def test_error_cases() -> None:
    for text, _ in CASES.values():
        same_as_pyyaml(text)


INSIDE = {
    "yaml 1.1 scalars": "a: yes\nb: 0x1F\nc: 1_000\nd: .inf\ne: ~\nf: -1.5\ng: off\nh: 1e3\n",
    "quoted": "a: 'it''s'\nb: \"two words\"\nc: ''\nd: 'a: b, c'\n",
    "comments": "# head\na: 1 # one\n\n  # indented\nb:   # empty line next\n  - x # item\n",
    "flow": "a: {b: 1, c: 'x, y', d: [1, 'two', {e: {}}], f: {}}\nb: []\nc: [ x , y ]\n",
    "plain with spaces": "description: Visit the zones, in order; then home.\n",
    "item keys on lines of their own": "a:\n  - b:\n      x: 1\n    c: 2\n",
    "nested lists": (
        "root:\n  sequence:\n    children:\n      - A: {}\n      -   B:\n            x: 1\n"
    ),
    "value after several spaces": "a:    {b: {c: 1}}\n",
    "list level with its key, in a list": "x:\n- a:\n  - 1\n  b: 2\n- 3\ny: 4\n",
    "lists level with their key": (
        "a:\n- 1\n- b:\n    c: [x]\n  d: 2\ne:\n  f:\n  - g: {}\n  h: 3\ni: 4\n"
    ),
}


@pytest.mark.parametrize("name", INSIDE)
def test_inside_the_subset(name: str) -> None:
    assert same_as_pyyaml(INSIDE[name])


OUTSIDE = {
    "tab": "a:\n\tb: 1\n",
    "carriage return": "a: 1\r\nb: 2\r\n",
    "non-ASCII": "a: caf\u00e9\n",
    "anchor and alias": "a: &x {b: 1}\nc: *x\n",
    "tag": "a: !!str 1\n",
    "python tag": "a: !!python/object:os.system x\n",
    "block scalar": "a: |\n  text\n",
    "folded scalar": "a: >\n  text\n",
    "multi-line plain": "a: one\n  two\n",
    "multi-line quoted": "a: 'one\n  two'\n",
    "escape": 'a: "tab\\there"\n',
    "document marker": "---\na: 1\n",
    "directive": "%YAML 1.1\n---\na: 1\n",
    "explicit key": "? a\n: 1\n",
    "duplicate key": "a: 1\na: 2\n",
    "duplicate flow key": "a: {b: 1, b: 2}\n",
    "boolean key": "on: 1\n",
    "null key": "null: 1\n",
    "empty value": "a:\nb: 1\n",
    "empty value at the end": "a:\n",
    "key after a list level with its key, deeper": "a:\n- 1\n  b: 2\n",
    "trailing comma": "a: {b: 1,}\n",
    "comment in quotes": "a: 'x #y'\n",
    "timestamp": "a: 2024-01-01\n",
    "root list": "- a\n",
    "root scalar": "a\n",
    "indented root": "  a: 1\n",
    "no space after colon": "a:1\n",
    "merge key": "<<: {a: 1}\n",
    "bad dedent": "a:\n    b: 1\n  c: 2\n",
    "empty": "",
    "only comments": "# nothing\n",
    "nested dash": "a:\n  - - 1\n",
    "dash alone": "a:\n  -\n    b: 1\n",
    "flow key without space": "a: {b:1}\n",
    "text after flow": "a: {b: 1} c\n",
    "single-pair mapping in a flow list": "a: [b: 1]\n",
    "second key of a one-line item": "a:\n  - b: 1\n    c: 2\n",
}


@pytest.mark.parametrize("name", OUTSIDE)
def test_outside_the_subset(name: str) -> None:
    assert quick_yaml.parse(OUTSIDE[name]) is None


_REGISTRY = make_registry()
_SEEDS = [p.read_text(encoding="utf-8") for p in ALL_YAML]


@_SETTINGS
@given(
    document=documents(_REGISTRY),
    flow=st.sampled_from([False, None]),
    indent=st.sampled_from([2, 4]),
)
def test_generated_documents(document: Any, flow: bool | None, indent: int) -> None:
    text = yaml.safe_dump(document, sort_keys=False, default_flow_style=flow, indent=indent,
                          width=1000)
    same_as_pyyaml(text)


@_SETTINGS
@given(text=mutated_texts(_SEEDS))
def test_mutated_files(text: str) -> None:
    try:
        yaml.safe_load(text)
    except Exception:  # PyYAML refuses it (not always with a YAMLError): so must the subset
        assert quick_yaml.parse(text) is None
        return
    same_as_pyyaml(text)
