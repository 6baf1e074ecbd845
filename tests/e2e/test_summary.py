"""The closing summary of ``sar-tree run`` (no ROS process starts)."""

from __future__ import annotations

import io
import json
from pathlib import Path

from sar_framework.orchestrate.outcome import Outcome, summarise


def test_a_repeated_failure_on_the_way_is_noted_once_with_its_count(tmp_path: Path) -> None:
    """Regression: a retried leaf that failed twice printed two identical note lines."""
    out = io.StringIO()
    failure = {"uid": "0.0.1.0.0.0", "name": "NavigateToZone",
               "message": "goal to ne_corner aborted: no path"}
    other = {"uid": "0.0.2", "name": "DetectSurvivor", "message": "service not available"}
    (tmp_path / "mission.json").write_text(json.dumps({
        "zones_visited": [{"id": "zone_a"}], "survivors": [], "ticks": 3,
        "wall_duration_s": 1.0, "sim_duration_s": 2.0,
        "failures": [failure, failure, other],
    }))
    summarise(lambda text: out.write(text + "\n"), tmp_path, Outcome("SUCCESS", 0),
              [tmp_path / "mission.json"], None)
    notes = [line for line in out.getvalue().splitlines() if "failed on the way" in line]
    assert notes == [
        "sar-tree run: note: NavigateToZone [0.0.1.0.0.0] failed on the way (2 times): "
        "goal to ne_corner aborted: no path",
        "sar-tree run: note: DetectSurvivor [0.0.2] failed on the way: service not available",
    ]
