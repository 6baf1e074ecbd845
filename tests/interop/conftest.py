"""Fixtures of the interop tests: the BehaviorTree.CPP checker, built once and cached."""

from __future__ import annotations

from pathlib import Path

import pytest

from interop.btcpp_build import build_checker, build_script_oracle, missing_toolchain


@pytest.fixture(scope="session")
def btcpp_checker() -> Path:
    """The checker executable, linked with BehaviorTree.CPP built from source (cached)."""
    reason = missing_toolchain()
    if reason is not None:
        pytest.skip(reason)
    return build_checker()


@pytest.fixture(scope="session")
def btcpp_script_oracle() -> Path:
    """BehaviorTree.CPP's own script engine behind a line-per-script program (cached)."""
    reason = missing_toolchain()
    if reason is not None:
        pytest.skip(reason)
    return build_script_oracle()
