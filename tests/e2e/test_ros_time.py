"""The same tree at two simulation speeds takes the same simulated time (ROS time)."""

from __future__ import annotations

from pathlib import Path

import pytest

from sar_framework.sim.params import sim_default

from .helpers import no_traceback, read_json, run_to_end

pytestmark = [pytest.mark.slow, pytest.mark.ros]

TREE = """\
format: 1
name: dwell_then_bounded_wait
root:
  sequence:
    name: Steps
    memory: true
    children:
      - Dwell: {name: Dwell, duration: 4.0}
      - failure_is_success:
          name: GiveUp
          child:
            timeout:
              name: Within3s
              duration: 3.0
              child: {Dwell: {name: Long, duration: 1000.0}}
"""


def _simulated(tmp_path: Path, speed: str) -> tuple[float, str]:
    tree = tmp_path / "timed.yaml"
    tree.write_text(TREE)
    report = tmp_path / f"report_{speed}"
    code, out = run_to_end([str(tree), "--speed", speed, "--timeout", "60"], report)
    assert code == 0, out
    assert no_traceback(out)
    return read_json(report / "mission.json")["sim_duration_s"], out


def test_waits_and_timeouts_take_the_same_simulated_time_at_any_speed(tmp_path: Path) -> None:
    """Regression: at --speed 20 a `timeout: 1.5` lasted 30 s of simulated time."""
    slow, slow_out = _simulated(tmp_path, "4")
    fast, fast_out = _simulated(tmp_path, "40")
    for speed, duration, out in ((4, slow, slow_out), (40, fast, fast_out)):
        # 4 s dwell + 3 s bound, ticks at 2 Hz; each of the two waits may end up to one /clock
        # step late, and /clock steps speed / max_update_hz simulated seconds (0.8 s at 40x)
        assert 7.0 <= duration <= 8.5 + 2 * clock_step(speed), out
        assert "Within3s [0.1.0] timeout: timed out after 3 s; Long: " in out
    assert abs(slow - fast) <= 1.0 + 2 * clock_step(40)


def clock_step(speed: float) -> float:
    """Simulated seconds between two /clock messages at ``speed``."""
    return speed / sim_default("max_update_hz")
