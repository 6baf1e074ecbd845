"""Each node kind names its builder in its declaration; declaring and checking import no py_trees.

"Where is X built?" has one answer: the ``build`` of X's declaration (a behaviour class or a
builder function, named as ``module:name`` so that reading declarations stays light).
"""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from sar_framework.engine.building.kind_builders import builder_of, resolve
from sar_framework.engine.nodes.node_kinds import KINDS
from sar_framework.engine.registry import default_registry


@pytest.mark.parametrize("key", sorted(KINDS))
def test_every_engine_kind_names_a_builder_that_resolves(key: str) -> None:
    kind = KINDS[key]
    assert isinstance(kind.build, str) and ":" in kind.build, kind.build
    assert callable(resolve(kind.build, key))
    assert callable(builder_of(kind))
    assert builder_of(kind) is builder_of(kind)  # worked out once


def test_every_plugin_kind_carries_its_builder() -> None:
    specs = default_registry().kind_plugins()
    assert specs
    for spec in specs:
        assert spec.kind.build is not None, spec.name
        assert callable(builder_of(spec.kind)), spec.name


def test_a_kind_without_a_builder_says_so() -> None:
    with pytest.raises(ValueError, match="node kind 'Nothing' names no builder"):
        resolve(None, "Nothing")


def test_declaring_validating_and_the_schema_import_no_py_trees(tmp_path: Path) -> None:
    tree = tmp_path / "tree.yaml"
    tree.write_text(textwrap.dedent("""\
        format: 1
        root:
          sequence:
            memory: true
            children:
              - retry: {num_failures: 2, child: {AlwaysFailure: {}}}
              - Timeout: {msec: 100, child: {Sleep: {msec: 10}}}
              - Script: {code: "x := 1"}
        """), encoding="utf-8")
    code = textwrap.dedent(f"""\
        import sys
        from sar_framework.engine.checking.schema import tree_schema
        from sar_framework.engine.checking.validate import validate_file
        from sar_framework.engine.registry import discover
        registry = discover([], builtins=False, entry_points=False)
        tree_schema(registry)
        result = validate_file({str(tree)!r}, registry=registry)
        assert result.ok, result.diagnostics
        assert "py_trees" not in sys.modules, "py_trees imported"
        """)
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=False)
    assert done.returncode == 0, done.stderr
