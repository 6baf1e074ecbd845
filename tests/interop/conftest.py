"""Fixtures of the interop tests: the BehaviorTree.CPP checker, built once and cached."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest

from interop.btcpp_build import build_checker, build_script_oracle, missing_toolchain


def _built(build: Callable[[], Path]) -> Path:
    """What ``build`` makes (cached), or skip the test where no toolchain can build it."""
    reason = missing_toolchain()
    if reason is not None:
        pytest.skip(reason)
    return build()


@pytest.fixture(scope="session")
def btcpp_checker() -> Path:
    """The checker executable, linked with BehaviorTree.CPP built from source (cached)."""
    return _built(build_checker)


@pytest.fixture(scope="session")
def btcpp_script_oracle() -> Path:
    """BehaviorTree.CPP's own script engine behind a line-per-script program (cached)."""
    return _built(build_script_oracle)
