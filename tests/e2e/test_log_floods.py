"""A decision the tree takes on every tick is shown once, with a count (sar-tree run)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from .helpers import DEFAULT_TREE, no_traceback, run_to_end

pytestmark = [pytest.mark.slow, pytest.mark.ros]


def test_a_blocked_zone_s_alternating_goals_are_collapsed_with_a_count(tmp_path: Path) -> None:
    """Regression: the reference tree with a blocked zone alternates its zone and base goals
    (the course's design) and printed 'Returning to base with 3 zone(s) unvisited' on every
    cycle: 1,256 lines in 30 s."""
    code, out = run_to_end([str(DEFAULT_TREE), "--sim-param", "blocked_zones:=['zone_b']",
                            "--timeout", "20"], tmp_path / "report")
    assert code == 1, out  # the reference tree never gets past a blocked zone: the timeout
    assert no_traceback(out)
    shown = [line for line in out.splitlines()
             if line.endswith("| Returning to base with 3 zone(s) unvisited.")]
    assert len(shown) == 1, out
    counted = re.search(r"\(repeated: .*'runner \| Returning to base with 3 zone\(s\) "
                        r"unvisited\.' (\d+) more times", out)
    assert counted is not None and int(counted.group(1)) >= 10, out
    assert len(out.splitlines()) < 60, out
