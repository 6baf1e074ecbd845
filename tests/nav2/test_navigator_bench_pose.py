"""NavigatorBench's pose after a run: read once TF shows the robot at rest, never a stale one."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from sar_framework.testing.nav2_navigators import NavigatorBench


class IdleExecutor:
    """An executor with nothing to run (TF never changes)."""

    def spin_once(self, timeout_sec: float = 0.0) -> None:
        del timeout_sec


def test_a_pose_tf_never_brings_past_the_run_is_an_error_naming_the_wait() -> None:
    stale = SimpleNamespace(executor=IdleExecutor(), _tf_stamp_ns=lambda: 5,
                            where=lambda: (0.0, 0.0))  # TF last stamped before the run ended
    with pytest.raises(AssertionError, match=r"at rest .* after the run.*\(0\.0, 0\.0\)"):
        NavigatorBench.settled_pose(stale, after_ns=10, timeout=0.2)


def test_a_pose_at_rest_after_the_run_is_read() -> None:
    stamps = iter(range(10, 10_000_000_000, 500_000_000))  # TF every 0.5 s of simulated time
    at_rest = SimpleNamespace(executor=IdleExecutor(), _tf_stamp_ns=lambda: next(stamps),
                              where=lambda: (2.0, -1.5))
    assert NavigatorBench.settled_pose(at_rest, after_ns=10) == (2.0, -1.5)
