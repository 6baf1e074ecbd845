"""The fast YAML path (libyaml compose) reads exactly what PyYAML's reference loader reads."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from sar_framework.engine.diagnostics import Diagnostic
from sar_framework.engine.reading import yaml_source

from ..checking.test_validate import CASES
from ..conftest import FIXTURES


def fast_values(text: str) -> tuple[Any, list[Diagnostic]]:
    root, problems = yaml_source.compose(text, "t.yaml")
    if root is None:
        return None, problems
    reader = yaml_source.Reader("t.yaml", problems)
    return reader.to_python(root), problems


def marks(node: yaml.Node) -> list[tuple[int, int]]:
    out = [(node.start_mark.line, node.start_mark.column)]
    if isinstance(node, yaml.MappingNode):
        for key, value in node.value:
            out += marks(key) + marks(value)
    elif isinstance(node, yaml.SequenceNode):
        for item in node.value:
            out += marks(item)
    return out


def corpus() -> list[str]:
    texts = [p.read_text(encoding="utf-8") for p in sorted(FIXTURES.rglob("*.yaml"))]
    return texts + [text for text, _ in CASES.values()]


def test_values_and_positions_match_the_reference_loader() -> None:
    compared = 0
    for text in corpus():
        try:
            expected = yaml.load(text, Loader=yaml.SafeLoader)  # pure Python
        except Exception:  # YAMLError, or ValueError & co. for a bad `!!int x`
            continue
        value, problems = fast_values(text)
        if problems:
            continue  # duplicate keys, aliases, tags: reported, checked elsewhere
        assert value == expected
        fast_root, _ = yaml_source.compose(text, "t.yaml")
        if fast_root is None:
            continue
        assert marks(fast_root) == marks(yaml.compose(text, Loader=yaml.SafeLoader))
        compared += 1
    assert compared >= 30


json_like = st.recursive(
    st.one_of(st.none(), st.booleans(), st.integers(), st.floats(allow_nan=False),
              st.text(max_size=8)),
    lambda inner: st.one_of(st.lists(inner, max_size=4),
                            st.dictionaries(st.text(max_size=5), inner, max_size=4)),
    max_leaves=20,
)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(value=json_like, flow=st.booleans())
def test_generated_values_round_trip_like_pyyaml(value: Any, flow: bool) -> None:
    text = yaml.safe_dump(value, default_flow_style=flow)
    got, problems = fast_values(text)
    assert problems == []
    assert got == yaml.load(text, Loader=yaml.SafeLoader)


def test_syntax_errors_are_worded_by_the_reference_parser() -> None:
    _, problems = yaml_source.compose("a: [1\nb: 2\n", "t.yaml")
    assert [str(p) for p in problems] == [
        "t.yaml:2:2: error: YAML: while parsing a flow sequence, expected ',' or ']', but got ':'"
    ]


def test_control_character() -> None:
    _, problems = yaml_source.compose("a: b\nc: \x07\n", "t.yaml")
    assert [str(p) for p in problems] == [
        "t.yaml:2:4: error: YAML: unacceptable character #x0007: special characters are not "
        "allowed"
    ]


def test_read_errors(tmp_path: Path) -> None:
    bad = tmp_path / "bad.yaml"
    bad.write_bytes(b"a: 1\nb: \xff\n")
    assert [str(p) for p in yaml_source.read(bad, "bad.yaml")[1]] == [
        "bad.yaml:2:4: error: file is not valid UTF-8"
    ]
    assert [str(p) for p in yaml_source.read(tmp_path / "no.yaml", "no.yaml")[1]] == [
        "no.yaml:1:1: error: no such file"
    ]
    bom = tmp_path / "bom.yaml"
    bom.write_bytes("\ufeffa: 1\n".encode())
    root, problems = yaml_source.read(bom, "bom.yaml")
    assert problems == [] and root is not None


def test_long_lines_use_the_same_composer_in_a_thread() -> None:
    text = "items: [" + ", ".join(f"{{name: n{i}, value: {i}}}" for i in range(2000)) + "]\n"
    assert len(text) > yaml_source._INLINE_MAX_LINE
    value, problems = fast_values(text)
    assert problems == [] and value == yaml.safe_load(text)


def test_compact_nesting_on_one_long_line() -> None:
    text = "a:\n" + "- " * 100_000 + "x\n"
    root, problems = yaml_source.compose(text, "t.yaml")
    assert problems == [] and root is not None


def test_multiple_documents() -> None:
    _, problems = yaml_source.compose("a: 1\n---\nb: 2\n", "t.yaml")
    assert [str(p) for p in problems] == [
        "t.yaml:2:1: error: YAML: expected a single document in the stream, but found another "
        "document"
    ]
