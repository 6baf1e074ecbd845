"""Fixtures of the interop tests: the BehaviorTree.CPP checker, built by the test set-up.

No test builds it: ``make test`` builds (or finds cached) both programs before pytest starts
(``make test-setup``, see :mod:`interop.btcpp_build`); a fixture only looks them up.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest

from interop.btcpp_build import (
    NotBuiltError,
    build_checker,
    build_script_oracle,
    missing_toolchain,
)


def _built(look_up: Callable[..., Path]) -> Path:
    """The program the set-up built; skip where no toolchain can build it.

    A missing build where a toolchain exists fails the test, naming the set-up command.
    """
    reason = missing_toolchain()
    if reason is not None:
        pytest.skip(reason)
    try:
        return look_up(build=False)
    except NotBuiltError as err:
        pytest.fail(str(err), pytrace=False)


@pytest.fixture(scope="session")
def btcpp_checker() -> Path:
    """The checker executable, linked with BehaviorTree.CPP built from source (cached)."""
    return _built(build_checker)


@pytest.fixture(scope="session")
def btcpp_script_oracle() -> Path:
    """BehaviorTree.CPP's own script engine behind a line-per-script program (cached)."""
    return _built(build_script_oracle)
