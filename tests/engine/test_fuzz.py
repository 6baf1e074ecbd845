"""Property-based fuzzing: random and mutated tree files give diagnostics, never exceptions."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from sar_framework.engine.api import load_tree
from sar_framework.engine.checking.validate import validate_file
from sar_framework.engine.diagnostics import TreeLoadError

from .conftest import FIXTURES, make_registry
from .strategies import documents, mutated_texts

_REGISTRY = make_registry()
_SEEDS = [p.read_text(encoding="utf-8") for p in sorted(FIXTURES.rglob("*.yaml"))]
_SETTINGS = settings(max_examples=300, deadline=None,
                     suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
_CONTEXT = {"zone_manager": object()}


def _check_file(path: Path) -> None:
    result = validate_file(path, registry=_REGISTRY)
    for d in result.diagnostics:
        assert d.location.line >= 1 and d.location.col >= 1
        assert d.message and "\n" not in d.message
        assert "Traceback" not in d.message
    if result.spec is not None:
        try:
            load_tree(path, context=_CONTEXT, registry=_REGISTRY)
        except TreeLoadError as exc:  # only constructor problems (the Exploding plugin)
            assert all("cannot construct" in d.message for d in exc.diagnostics)


@_SETTINGS
@given(document=documents(_REGISTRY))
def test_generated_documents(document: Any, tmp_path_factory: Any) -> None:
    path = tmp_path_factory.mktemp("fuzz") / "tree.yaml"
    path.write_text(yaml.safe_dump(document, sort_keys=False), encoding="utf-8")
    _check_file(path)


@_SETTINGS
@given(text=mutated_texts(_SEEDS))
def test_mutated_files(text: str, tmp_path_factory: Any) -> None:
    path = tmp_path_factory.mktemp("mut") / "tree.yaml"
    path.write_text(text, encoding="utf-8", errors="surrogatepass")
    _check_file(path)


@_SETTINGS
@given(data=st.binary(max_size=200))
def test_random_bytes(data: bytes, tmp_path_factory: Any) -> None:
    path = tmp_path_factory.mktemp("bytes") / "tree.yaml"
    path.write_bytes(data)
    _check_file(path)


def test_deep_nesting_is_a_diagnostic(tmp_path: Path) -> None:
    path = tmp_path / "deep.yaml"
    path.write_text("format: 1\nroot: " + "[" * 100_000 + "]" * 100_000 + "\n")
    result = validate_file(path, registry=_REGISTRY)
    assert result.spec is None and result.diagnostics


def test_deep_tree_is_a_diagnostic(tmp_path: Path) -> None:
    path = tmp_path / "deep_tree.yaml"
    body = "{inverter: {child: " * 400 + "{Tick: {}}" + "}}" * 400
    path.write_text(f"format: 1\nroot: {body}\n")
    result = validate_file(path, registry=_REGISTRY)
    assert [d.message for d in result.diagnostics] == [
        "the tree is nested deeper than 200 levels"
    ]
