"""The reference mission with Nav2's navigator shape (trees/examples/search_and_rescue_nav2.yaml).

One ``sar-tree run`` for the module, recorded, with a phantom obstacle in the doorway of
zone_b's room (``phantom_obstacles:=['1.0:1.0:0.7']``, in both costmaps): from zone_a
the planner finds no path (NO_VALID_PATH, 208), the subtree's ClearGlobalCostmap-Context
clears the global costmap and the replan succeeds; FollowPath then meets the phantom in
the local costmap (NO_VALID_CONTROL, 106) and ClearLocalCostmap-Context clears it. The
mission then goes on as the reference one: same spec lines, same survivors, same report
file. The recovery shows on the console (reason lines), in mission.json (``failures``) and
in the recording, read by the independent readers of tests/recording.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
from recording.test_mission_recording import read_with_mcap_ros2, read_with_rosbags

from .helpers import (
    FAST,
    NAV2_TREE,
    SPEC_LINES,
    in_order,
    no_traceback,
    read_json,
    read_jsonl,
    run_to_end,
)

pytestmark = [pytest.mark.slow, pytest.mark.ros]

DOORWAY_PHANTOM = "phantom_obstacles:=['1.0:1.0:0.7']"
PLANNER_RECOVERY = "ComputePathToPose [0.0.1.1.0.2.0] retry: recovery 1/1 done " \
    "(ClearEntireCostmap ClearGlobalCostmap-Context) after ComputePathToPose: " \
    "compute_path_to_pose aborted (error code 208)"
CONTROLLER_RECOVERY = "FollowPath [0.0.1.1.0.3] retry: recovery 1/1 done (ClearEntireCostmap " \
    "ClearLocalCostmap-Context) after FollowPath: follow_path aborted (error code 106)"


@pytest.fixture(scope="module")
def nav2_run(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    folder = tmp_path_factory.mktemp("nav2_mission")
    record = folder / "mission.mcap"
    code, out = run_to_end([str(NAV2_TREE), "--speed", FAST, "--sim-param", DOORWAY_PHANTOM,
                            "--record", str(record)], folder / "report", timeout=180.0)
    return {"code": code, "out": out, "report": folder / "report", "record": record}


def test_same_spec_lines_survivors_and_report_file_as_the_reference(nav2_run: dict) -> None:
    out = nav2_run["out"]
    assert nav2_run["code"] == 0, out
    in_order(out, SPEC_LINES)
    assert out.count("Mission complete.") == 1 and no_traceback(out)
    records = read_jsonl(nav2_run["report"] / "reports.jsonl")
    assert [(r["survivor_id"], r["x"], r["y"], r["frame_id"]) for r in records] == [
        ("survivor_1", -2.5, 3.2, "map"), ("survivor_2", 4.1, -2.5, "map")]
    mission = read_json(nav2_run["report"] / "mission.json")
    assert mission["outcome"] == "SUCCESS" and mission["at_base"] is True
    assert [z["id"] for z in mission["zones_visited"]] == ["zone_a", "zone_b", "zone_c",
                                                           "zone_d"]
    assert [(s["id"], s["x"], s["y"], s["acknowledged"]) for s in mission["survivors"]] == [
        ("survivor_1", -2.5, 3.2, True), ("survivor_2", 4.1, -2.5, True)]


def test_the_recovery_is_on_the_console_and_in_mission_json(nav2_run: dict) -> None:
    out = nav2_run["out"]
    assert nav2_run["code"] == 0, out
    for line in (PLANNER_RECOVERY, CONTROLLER_RECOVERY):
        assert f"WARN: {line}" in out, out
    # the failures come before the recoveries that answer them, all on the way to zone_b
    in_order(out, ["--- Zone 2/4: zone_b (3.50, 3.00) ---", "Reached zone_b."])
    failures = read_json(nav2_run["report"] / "mission.json")["failures"]
    said = [f"{f['name']} [{f['uid']}] {f['what']}: {f['message']}" for f in failures]
    assert any(s.startswith(PLANNER_RECOVERY) for s in said), said
    assert any(s.startswith(CONTROLLER_RECOVERY) for s in said), said
    assert {f["what"] for f in failures} <= {"failure", "retry", "cancel"}


def clearings(status_messages: list[Any]) -> set[str]:
    """Names of the ClearEntireCostmap leaves some tree status shows ticked (RUNNING: the
    RecoveryNode resets its recovery in the tick the call is answered)."""
    seen = set()
    for data in status_messages:
        for _uid, name, kind, status, _text, visited in json.loads(data)["nodes"]:
            if kind == "ClearEntireCostmap" and status in {"RUNNING", "SUCCESS"} and visited:
                seen.add(name)
    return seen


def test_the_recording_holds_the_recovery_for_both_readers(nav2_run: dict) -> None:
    record: Path = nav2_run["record"]
    assert nav2_run["code"] == 0, nav2_run["out"]
    expected = {"ClearGlobalCostmap-Context", "ClearLocalCostmap-Context"}
    by_rosbags = read_with_rosbags(record)
    by_mcap = read_with_mcap_ros2(record)
    for events in ([m for _s, m in by_rosbags["/sar_mission/events"]],
                   by_mcap["/sar_mission/events"]):
        retries = [(e.node_name, e.message) for e in events if e.kind == "retry"]
        assert any("ClearGlobalCostmap-Context" in m for n, m in retries
                   if n == "ComputePathToPose"), retries
        assert any("ClearLocalCostmap-Context" in m for n, m in retries
                   if n == "FollowPath"), retries
    assert clearings([m.data for _s, m in by_rosbags["/sar_tree/status"]]) >= expected
    assert clearings([m.data for m in by_mcap["/sar_tree/status"]]) >= expected
