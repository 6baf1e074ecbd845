"""Shared fixtures for the engine tests: test plugin registries and a tree checker."""

from __future__ import annotations

import sys
import textwrap
from collections.abc import Callable
from pathlib import Path

import pytest

from sar_framework.engine.api import load_tree
from sar_framework.engine.checking.validate import ValidationResult, validate_file
from sar_framework.engine.diagnostics import TreeLoadError
from sar_framework.engine.registry import Registry, discover

HERE = Path(__file__).parent
GENERIC_PLUGINS = HERE / "plugins_for_tests" / "generic"
MISSION_PLUGINS = HERE / "plugins_for_tests" / "mission"
FIXTURES = HERE / "fixtures"
REPO = HERE.parent.parent
VENV_BIN = Path(sys.executable).parent


def make_registry() -> Registry:
    """The generic and mission stand-in plugins, without built-ins or entry points."""
    return discover([GENERIC_PLUGINS, MISSION_PLUGINS], builtins=False, entry_points=False)


@pytest.fixture(scope="session")
def registry() -> Registry:
    reg = make_registry()
    assert reg.diagnostics == []
    return reg


Checker = Callable[..., list[str]]


@pytest.fixture
def tree_dir(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.chdir(tmp_path)
    return tmp_path


def write(directory: Path, name: str, text: str) -> Path:
    path = directory / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(textwrap.dedent(text).lstrip("\n"), encoding="utf-8")
    return path


@pytest.fixture
def validate(tree_dir: Path, registry: Registry) -> Callable[..., ValidationResult]:
    """Write files (name -> text) into a temp dir and validate the first one."""

    def run(text: str | None = None, files: dict[str, str] | None = None) -> ValidationResult:
        all_files = dict(files or {})
        if text is not None:
            all_files = {"tree.yaml": text, **all_files}
        for name, body in all_files.items():
            write(tree_dir, name, body)
        return validate_file(next(iter(all_files)), registry=registry)

    return run


@pytest.fixture
def check(validate: Callable[..., ValidationResult]) -> Checker:
    """Validate and return the diagnostics as printed."""

    def run(text: str | None = None, files: dict[str, str] | None = None) -> list[str]:
        return [str(d) for d in validate(text, files).diagnostics]

    return run


def load_problems(path: Path, registry: Registry) -> str:
    """The text of the :class:`TreeLoadError` that loading the tree at ``path`` raises."""
    with pytest.raises(TreeLoadError) as error:
        load_tree(path, {}, registry=registry)
    return str(error.value)
