"""How a mission ends (``completion``): the default follows the tree's end (no ROS)."""

from __future__ import annotations

from pathlib import Path

import pytest

from sar_framework import load_spec
from sar_framework.mission.completion import describe_completion, resolve_completion

REPO = Path(__file__).resolve().parents[2]

GO_HOME_AFTER_A_BUDGET = """\
format: 1
name: budget_then_home
root:
  sequence:
    name: Mission
    memory: true
    children:
      - failure_is_success:
          child:
            timeout:
              duration: 60
              child:
                repeat:
                  num_success: -1
                  child: {AdvanceZone: {}}
      - NavigateToBase: {}
"""


@pytest.mark.parametrize("tree", ["trees/search_and_rescue.yaml",
                                  "trees/examples/bounded_mission.yaml",
                                  "trees/examples/patrol_skip_unreachable.yaml"])
def test_shipped_missions_end_at_rest_on_their_one_shot(tree: str) -> None:
    mode, why = resolve_completion("auto", load_spec(REPO / tree))
    assert mode == "rest"
    assert why.startswith("auto: the tree ends with one_shot NavigateToBaseOneShot")


def test_a_tree_ending_with_a_leaf_runs_once(tmp_path: Path) -> None:
    path = tmp_path / "t.yaml"
    path.write_text(GO_HOME_AFTER_A_BUDGET)
    spec = load_spec(path)
    assert resolve_completion("auto", spec)[0] == "once"
    assert describe_completion("rest", spec) == (
        "completion: rest (set in the parameters; the mission ends when the tree is at rest)")
    with pytest.raises(ValueError, match="auto, once, rest, forever"):
        resolve_completion("terminal", spec)
