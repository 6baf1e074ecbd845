"""py_trees' spellings name declared kinds only, with attributes those kinds declare."""

from __future__ import annotations

from sar_framework.engine.nodes.control_kinds import CONTROL_KINDS
from sar_framework.engine.nodes.node_kinds import PY_TREES_KINDS
from sar_framework.engine.nodes.py_trees_spellings import PY_TREES_SPELLINGS
from sar_framework.interop.mapping import builtin_for


def test_each_spelling_resolves_to_declared_kinds() -> None:
    btcpp = {k.key for k in CONTROL_KINDS}
    for spelling in PY_TREES_SPELLINGS:
        assert spelling.btcpp_id in btcpp, spelling.btcpp_id
        kind = PY_TREES_KINDS[spelling.kind]
        for name, value in spelling.fixed:
            attr = kind.attr(name)
            assert attr is not None, (spelling.kind, name)
            assert attr.enum is None or value in attr.enum, (spelling.kind, name, value)


def test_export_reads_the_one_table() -> None:
    for spelling in PY_TREES_SPELLINGS:
        entry = builtin_for(spelling.kind, dict(spelling.fixed))
        assert entry is not None and entry.btcpp_id == spelling.btcpp_id, spelling
