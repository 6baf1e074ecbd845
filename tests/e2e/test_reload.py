"""``sar-tree run --reload``: the tree file edited mid-mission, in the embedded simulator.

One full-stack run: an invalid edit is refused with its diagnostic and the mission goes on;
a valid edit (a Dwell added to the patrol) is swapped in while NavigateToZone drives; the
mission then completes with every zone visited and each survivor reported once, and
mission.json lists both reloads. The reloads need a slow simulator; once the swap is done the
test sets the simulator's speed as a user does (``ros2 param set /sar_sim speed``), so the
rest of the mission does not take a slow run's wall time.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from sar_framework.testing.sim_control import set_sim_params
from sar_framework.testing.spin import ros_node

from .helpers import DEFAULT_TREE, FAST, no_traceback, read_json, read_jsonl, sar_tree_run

pytestmark = [pytest.mark.slow, pytest.mark.ros]

SPEED = "8"  # slow enough for two reloads (a save is seen within about a wall second)


def test_run_reload_refuses_a_bad_edit_and_swaps_a_good_one_mid_mission(tmp_path: Path) -> None:
    tree = tmp_path / "mission.yaml"
    text = DEFAULT_TREE.read_text(encoding="utf-8")
    tree.write_text(text, encoding="utf-8")
    bad = text.replace("            - AdvanceZone: {}", "            - AdvanceZon: {}")
    good = text.replace("            - AdvanceZone: {}",
                        "            - AdvanceZone: {}\n"
                        "            - Dwell: {name: Linger, duration: 0.5}")
    assert bad != text and good != text
    report = tmp_path / "report"
    process = sar_tree_run([str(tree), "--speed", SPEED, "--reload"], report)
    try:
        process.wait_for_output(r"--- Zone 1/4: zone_a", timeout=90)
        tree.write_text(bad, encoding="utf-8")
        refused = process.wait_for_output(r"Reload of \S+ refused, the tree goes on: (.*)",
                                          timeout=30)
        assert f"{tree}:" in refused.group(1) and "AdvanceZon" in refused.group(1)
        tree.write_text(good, encoding="utf-8")
        process.wait_for_output(r"Tree swapped from \S+: 1 added \(Linger\)", timeout=30)
        with ros_node("e2e_reload_speed") as (node, executor):
            (sped_up,) = set_sim_params(node, executor, speed=float(FAST))
        assert sped_up.successful, sped_up.reason
        code = process.wait(timeout=120)
    finally:
        process.stop()
    out = process.output
    assert code == 0, out
    assert no_traceback(out)
    assert "sar-tree run: Mission SUCCESS" in out
    assert "tree reloads: 1 swapped, 1 refused" in out
    summary = read_json(report / "mission.json")
    assert [z["id"] for z in summary["zones_visited"]] == ["zone_a", "zone_b", "zone_c", "zone_d"]
    assert summary["base_reached"] is not None
    assert [(s["id"], s["acknowledged"]) for s in summary["survivors"]] == [
        ("survivor_1", True), ("survivor_2", True)]
    reports = read_jsonl(report / "reports.jsonl")
    assert sorted(r["survivor_id"] for r in reports) == ["survivor_1", "survivor_2"]
    assert summary["navigation_goals"] == 5  # one per zone and the base: none sent again
    reloads = summary["reloads"]
    assert [r["what"] for r in reloads] == ["reload_refused", "tree_swapped"]
    assert "AdvanceZon" in reloads[0]["message"]
    assert "1 added (Linger)" in reloads[1]["message"] and "halted" not in reloads[1]["message"]
    # The new leaf ran in the zones after the swap.
    assert summary["node_statuses"].get("0.0.5") == "SUCCESS"
