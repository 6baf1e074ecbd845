"""The BehaviorTree.CPP checker is built by the test run's set-up, never by a test."""

from __future__ import annotations

import os
import re
import subprocess
import sys
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


def test_the_sources_are_found_where_the_set_up_finds_the_ros_overlay(tmp_path: Path) -> None:
    overlay = tmp_path / "overlay_src"
    (overlay / "behaviortree_cpp").mkdir(parents=True)
    env = dict(os.environ, SAR_ROS_OVERLAY_SRC=str(overlay))
    printed = subprocess.run(
        [sys.executable, "-c", "from interop import btcpp_build; "
         "print(btcpp_build.BTCPP_SOURCE); print(btcpp_build.missing_toolchain())"],
        cwd=REPO / "tests", env=env, capture_output=True, text=True, timeout=60,
        check=True).stdout.splitlines()
    assert printed[0] == str(overlay / "behaviortree_cpp")
    assert printed[1] == f"no BehaviorTree.CPP sources at {overlay / 'behaviortree_cpp'}"
