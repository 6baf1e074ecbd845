"""One clock: the same tree with the same fault fails the same nodes, in the same order, at
``--speed 5`` and ``--speed 10``, each bound after its simulated seconds (the events' stamps).

The fault: no detect server. DetectSurvivor's ``server_timeout_s`` (5 s) and the visit's
``timeout`` (60 s) race. When leaf bounds counted wall seconds, the detect bound fired
first at 5x (about 15 + 25 simulated seconds) and the visit timeout first at 10x (15 + 50 > 60).

Each run is checked against its own stamps: the detect bound fires 5 to 10 simulated seconds
after DetectSurvivor started (a wall-second bound: 25 at 5x, 50 at 10x). Comparing absolute
times across the two runs tested the load instead: the simulator does not wait for the
runner, so a tick the loaded runner takes 0.08 s late is 0.8 s late in simulated time at 10x.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from sar_framework.events.event import REASON_KINDS, EventKind, MissionEvent
from sar_framework.events.jsonl import EVENTS_FILE, read_events

from .helpers import no_traceback, run_to_end

pytestmark = [pytest.mark.slow, pytest.mark.ros]

DETECT_BOUND_S = 5.0  # DetectSurvivor's server_timeout_s below
DETECT = "0.0.0.0.1"
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


def _run(tmp_path: Path, speed: str) -> list[MissionEvent]:
    tree = tmp_path / "two_speeds.yaml"
    tree.write_text(TREE)
    report = tmp_path / f"report_{speed}"
    # No report server either: the tree reports nothing, so it would only cost CPU.
    code, out = run_to_end([str(tree), "--speed", speed, "--no-detect-server",
                            "--no-report-server", "--timeout", "90"], report, timeout=150)
    assert code == 0, out
    assert no_traceback(out)
    return list(read_events(report / EVENTS_FILE))


def _reasons(events: list[MissionEvent]) -> list[tuple[str, str]]:
    return [(e.kind.value, e.node_uid) for e in events if e.kind in REASON_KINDS]


def _detect_bound_s(events: list[MissionEvent]) -> float:
    """Simulated seconds from DetectSurvivor's first tick to its failure."""
    started = next(e.sim_s for e in events if e.kind is EventKind.STATUS
                   and e.node_uid == DETECT and e.status == "RUNNING")
    failed = next(e.sim_s for e in events if e.kind is EventKind.FAILURE and e.node_uid == DETECT)
    return failed - started


def test_the_same_nodes_fail_in_the_same_order_each_bound_in_simulated_time(tmp_path: Path
                                                                             ) -> None:
    """Regression: which of a leaf's bound and a tree's timeout fired first changed with
    --speed (leaf bounds counted wall seconds, decorators ROS time)."""
    slow = _run(tmp_path, "5")
    fast = _run(tmp_path, "10")
    assert _reasons(slow) == _reasons(fast)
    assert _reasons(slow)[:2] == [
        ("failure", DETECT),  # DetectSurvivor: no server within 5 s (ROS time)
        ("skip", "0.0"),
    ]
    for events in (slow, fast):
        assert DETECT_BOUND_S <= _detect_bound_s(events) < 2 * DETECT_BOUND_S, [
            (e.kind.value, e.node_uid, e.status, e.sim_s) for e in events]
