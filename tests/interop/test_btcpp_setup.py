"""The BehaviorTree.CPP checker is built by the test run's set-up, never by a test."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from interop.btcpp_build import NotBuiltError, build_checker, build_script_oracle

REPO = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("look_up", [build_checker, build_script_oracle])
def test_a_program_missing_from_the_cache_is_not_built_by_a_look_up(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, look_up) -> None:
    monkeypatch.setenv("SAR_BTCPP_CACHE", str(tmp_path / "cache"))
    with pytest.raises(NotBuiltError, match="run `make test-setup` first"):
        look_up(build=False)
    assert not (tmp_path / "cache").exists(), "a look-up must not start a build"


def test_make_test_and_test_fast_set_the_checker_up_first() -> None:
    makefile = (REPO / "Makefile").read_text()
    for target in ("test", "test-fast"):
        prerequisites = re.search(rf"^{target}:([^#\n]*)", makefile, re.MULTILINE)
        assert prerequisites and "test-setup" in prerequisites.group(1).split(), target
    recipe = re.search(r"^test-setup:.*\n\t(.*)", makefile, re.MULTILINE)
    assert recipe and "tests/interop/btcpp_build.py" in recipe.group(1)
