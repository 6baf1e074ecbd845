"""One clock: the same tree with the same fault fails the same nodes, in the same order, at
the same simulated times, at ``--speed 5`` and ``--speed 10`` (the events' stamps).

The fault: no detect server. DetectSurvivor's ``server_timeout_s`` (5 s) and the visit's
``timeout`` (60 s) race. When leaf bounds counted wall seconds, the detect bound fired
first at 5x (about 15 + 25 simulated seconds) and the visit timeout first at 10x (15 + 50 > 60).
10x, not 20x: a runner tick delayed by a loaded machine shows as
speed times its wall delay in simulated time.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from sar_framework.events.event import REASON_KINDS
from sar_framework.events.jsonl import EVENTS_FILE, read_events

from .helpers import no_traceback, read_json, run_to_end

pytestmark = [pytest.mark.slow, pytest.mark.ros]

TICK_S = 0.5  # the mission's tick_rate_hz: 2
TREE = """\
format: 1
name: two_speeds
root:
  sequence:
    name: Mission
    memory: true
    children:
      - failure_is_success:
          name: SkipVisit
          child:
            timeout:
              name: VisitWithin60s
              duration: 60
              child:
                sequence:
                  name: Visit
                  memory: true
                  children:
                    - NavigateToZone: {}
                    - DetectSurvivor: {id: detect, server_timeout_s: 5}
      - one_shot:
          name: HomeOnce
          policy: on_completion
          child: {NavigateToBase: {}}
"""


def _reasons(tmp_path: Path, speed: str) -> list[tuple[str, str, float]]:
    tree = tmp_path / "two_speeds.yaml"
    tree.write_text(TREE)
    report = tmp_path / f"report_{speed}"
    code, out = run_to_end([str(tree), "--speed", speed, "--no-detect-server",
                            "--timeout", "90"], report, timeout=150)
    assert code == 0, out
    assert no_traceback(out)
    start = read_json(report / "status.json")["sim_start_s"]
    return [(e.kind.value, e.node_uid, round(e.sim_s - start, 3))
            for e in read_events(report / EVENTS_FILE) if e.kind in REASON_KINDS]


def test_the_same_nodes_fail_in_the_same_order_at_the_same_simulated_times(tmp_path: Path
                                                                           ) -> None:
    """Regression: which of a leaf's bound and a tree's timeout fired first changed with
    --speed (leaf bounds counted wall seconds, decorators ROS time)."""
    slow = _reasons(tmp_path, "5")
    fast = _reasons(tmp_path, "10")
    assert [(kind, uid) for kind, uid, _ in slow] == [(kind, uid) for kind, uid, _ in fast]
    assert [(kind, uid) for kind, uid, _ in slow][:2] == [
        ("failure", "0.0.0.0.1"),  # DetectSurvivor: no server within 5 s (ROS time)
        ("skip", "0.0"),
    ]
    for (_, uid, at_slow), (_, _, at_fast) in zip(slow, fast, strict=True):
        assert abs(at_slow - at_fast) <= TICK_S + 0.25, (uid, at_slow, at_fast)
