"""Hypothesis strategies: tree documents, mostly well-formed, with random damage."""

from __future__ import annotations

from typing import Any

from hypothesis import strategies as st

from sar_framework.engine.nodes.node_kinds import KINDS, SUBTREE, Attr, AttrType, leaf_attrs
from sar_framework.engine.registry import Registry

_JUNK_KEYS = st.sampled_from(["bogus", "nmae", "memroy", "child", "children", "id", ""])

scalars = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(min_value=-3, max_value=200),
    st.floats(allow_nan=True, allow_infinity=True, width=32),
    st.text(alphabet="abcAB_ 1.-:", max_size=6),
)
junk = st.recursive(
    scalars,
    lambda inner: st.one_of(
        st.lists(inner, max_size=3),
        st.dictionaries(st.text(alphabet="abc", max_size=3), inner, max_size=3),
    ),
    max_leaves=5,
)


def _good_value(attr: Attr, ids: list[str]) -> st.SearchStrategy[Any]:
    """A value of the right type, not necessarily within the declared bounds."""
    if attr.enum is not None:
        return st.sampled_from(list(attr.enum))
    if attr.ref is not None:
        return st.sampled_from([*ids, "nope"])
    if attr.name == "selected":
        return st.lists(st.sampled_from(["A", "B", "Tick"]), max_size=2)
    return {
        AttrType.STRING: st.text(alphabet="abAB", max_size=4),
        AttrType.INTEGER: st.one_of(
            st.integers(1, 5), st.integers(-2, 120), st.sampled_from([1.0, 2.0])
        ),
        AttrType.NUMBER: st.one_of(st.floats(0.5, 50), st.integers(-2, 5), st.floats(-2, 200)),
        AttrType.BOOLEAN: st.booleans(),
        AttrType.STRINGS: st.lists(st.text(alphabet="ab", max_size=2), max_size=2),
    }.get(attr.type, junk)


def documents(registry: Registry, max_depth: int = 4) -> st.SearchStrategy[Any]:
    """Tree documents as plain Python values (for yaml.safe_dump)."""
    plugins = {p.name: leaf_attrs(p) for p in registry}
    ids = ["a", "b", "detect"]

    @st.composite
    def node(draw: st.DrawFn, depth: int) -> Any:
        roll = draw(st.integers(0, 99))
        if roll < 2:
            return draw(junk)
        if roll < 5:
            return {SUBTREE: draw(st.sampled_from(["s1", "missing", "", 3]))}
        leaf_only = depth >= max_depth
        choices = list(plugins) if leaf_only else [*KINDS, *plugins, *plugins]
        if roll < 8:
            key = draw(st.sampled_from(["Tic", "eternal_guard", "Sequence"]))
        else:
            key = draw(st.sampled_from(choices))
        attrs_decl = KINDS[key].attrs if key in KINDS else plugins.get(key, ())
        attrs: dict[str, Any] = {}
        for attr in attrs_decl:
            present = draw(st.integers(0, 19))
            if present == 0 and attr.required:
                continue  # drop a required attribute now and then
            if not attr.required and present < 10:
                continue
            if attr.type is AttrType.NODE:
                attrs[attr.name] = draw(node(depth + 1))
            elif attr.type is AttrType.NODES:
                attrs[attr.name] = draw(st.lists(node(depth + 1), min_size=0, max_size=3))
            elif present == 19:
                attrs[attr.name] = draw(junk)
            else:
                attrs[attr.name] = draw(_good_value(attr, ids))
        if draw(st.integers(0, 39)) == 0:
            attrs[draw(_JUNK_KEYS)] = draw(junk)
        if draw(st.integers(0, 59)) == 0:
            return {key: attrs, "name": "extra"}
        if draw(st.integers(0, 59)) == 0:
            return {key: None}
        return {key: attrs}

    @st.composite
    def document(draw: st.DrawFn) -> Any:
        damage = draw(st.integers(0, 99))  # < 25: one top-level problem
        doc: dict[str, Any] = {}
        if damage != 0:
            doc["format"] = 1 if damage > 3 else draw(st.sampled_from([1.0, 2, "1", None]))
        if draw(st.booleans()):
            doc["name"] = draw(st.text(max_size=5)) if damage not in (4, 5) else draw(junk)
        if draw(st.integers(0, 4)) == 0:
            doc["subtrees"] = {"s1": draw(node(2))}
        if damage not in (6, 7):
            doc["root"] = draw(node(1))
        if damage in (8, 9):
            doc[draw(_JUNK_KEYS)] = draw(junk)
        if damage == 10:
            return draw(junk)
        return doc

    return document()


_YAML_BITS = st.sampled_from([
    ":", "-", " ", "\n", "\t", "{", "}", "[", "]", "&a ", "*a", "!!python/object:os.system ",
    "!x ", "<<: ", "'", '"', "#", "|", ">", "?", ",", "%YAML 1.1\n", "---\n", "\x00", "\ufeff",
    "\\", "é", "0x1F", ".nan", "~", "yes", "2024-01-01", "memory: true", "children: []",
    "!!timestamp ", "!!bool ", "!!int ", "!!float ", "!!null ", "!!str ", "!!binary ", "!!set ",
    "  ", " # c", "{}", "- ", "on", "null", "''", "1_000", "-1", "\r\n", "a: b", "{x: 1}",
])


@st.composite
def mutated_texts(draw: st.DrawFn, seeds: list[str]) -> str:
    """One of ``seeds`` with a few random edits (YAML-significant bits, cuts, copies)."""
    text = draw(st.sampled_from(seeds))
    for _ in range(draw(st.integers(1, 6))):
        pos = draw(st.integers(0, len(text)))
        op = draw(st.integers(0, 3))
        if op == 0:  # insert a YAML-significant bit
            text = text[:pos] + draw(_YAML_BITS) + text[pos:]
        elif op == 1:  # delete a span
            text = text[:pos] + text[pos + draw(st.integers(1, 20)):]
        elif op == 2:  # duplicate a line
            lines = text.split("\n")
            i = draw(st.integers(0, len(lines) - 1))
            lines.insert(i, lines[i])
            text = "\n".join(lines)
        else:  # random characters
            text = text[:pos] + draw(st.text(max_size=4)) + text[pos:]
    return text
