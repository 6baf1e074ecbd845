"""The survivor leaves' references are checked like any other: file, line, column (no ROS)."""

from __future__ import annotations

from pathlib import Path

import pytest

from sar_framework.engine.api import TreeLoadError, load_spec

FIXTURE = Path(__file__).resolve().parent / "fixtures" / "survivor_branch.yaml"

BAD = """\
format: 1
name: bad
root:
  sequence:
    name: S
    memory: true
    children:
      - DetectSurvivor: {id: detect}
      - RegisterSurvivor: {id: register, detector: detect, service_name: 3}
      - BroadcastSurvivorTF: {id: broadcast, detector: detect, registrar: detect}
      - LogSurvivorNotRegistered: {registrar: nobody}
"""


def test_the_fleet_survivor_branch_is_a_valid_tree() -> None:
    assert load_spec(FIXTURE).name == "fleet_survivor_branch"


def test_bad_survivor_references_are_reported_at_their_place(tmp_path: Path) -> None:
    tree = tmp_path / "bad.yaml"
    tree.write_text(BAD)
    with pytest.raises(TreeLoadError) as caught:
        load_spec(tree)
    lines = str(caught.value).splitlines()
    assert f"{tree}:9:74: error: 'service_name' must be a string, got integer 3" in lines
    assert (f"{tree}:10:75: error: 'registrar' must name a RegisterSurvivor leaf, but "
            "'detect' is a DetectSurvivor") in lines
    assert f"{tree}:11:47: error: 'registrar' names no leaf: there is no id 'nobody'" in lines
