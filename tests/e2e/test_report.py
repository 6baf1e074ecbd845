"""The mission report from synthetic run files (no ROS, no processes)."""

from __future__ import annotations

import json
from pathlib import Path

from sar_plugins.sar.events import SarKind
from sar_plugins.sar.report import mission_layout

from sar_framework.events.event import EventKind, MissionEvent
from sar_framework.events.jsonl import EVENTS_FILE, EventFileWriter
from sar_framework.report import MissionInputs, summarise, write_report
from sar_framework.report_map import BLOCKED_COLOUR, fit_left, shift_into

from .helpers import DEFAULT_TREE, REPO

PARAMS = REPO / "config" / "mission_params.yaml"


def _events(folder: Path, *events: MissionEvent) -> None:
    writer = EventFileWriter(folder / EVENTS_FILE)
    for seq, event in enumerate(events, 1):
        writer(event.numbered(seq))
    writer.close()


def _files(folder: Path) -> None:
    _events(
        folder,
        MissionEvent(SarKind.ZONE_REACHED, sim_s=19.0, wall_s=1.0, fields={"zone_id": "zone_a"},
                     message="whatever words", position=(-3.0, 3.0, 0.0)),
        MissionEvent(SarKind.SURVIVOR_BROADCAST, sim_s=20.0, wall_s=1.1,
                     fields={"survivor_id": "survivor_1"}, position=(-2.5, 3.2, 0.0)),
        MissionEvent(SarKind.SURVIVOR_BROADCAST, sim_s=30.0, wall_s=1.5,
                     fields={"survivor_id": "survivor_2"}, position=(4.1, -2.5, 0.0)),
        MissionEvent(SarKind.SURVIVOR_REFUSED, sim_s=30.5, wall_s=1.6,
                     fields={"survivor_id": "survivor_2"}, message="refuse_all is set",
                     position=(4.1, -2.5, 0.0)),
        MissionEvent(SarKind.BASE_REACHED, sim_s=40.0, wall_s=2.0, node_uid="0.1.0",
                     node_name="NavigateToBase", position=(0.0, 0.0, 0.0)),
    )
    (folder / "status.json").write_text(json.dumps({
        "status": "SUCCESS", "ticks": 80, "wall_first_tick_s": 0.5, "sim_start_s": 1.0,
        "sim_end_s": 41.0, "wall_duration_s": 2.5, "nodes": {"0": "SUCCESS"},
        "events": [], "failures": []}))
    trace = [{"sim_s": 0.0, "event": "start", "x": 0.0, "y": 0.0, "yaw": 0.0},
             {"sim_s": 1.0, "event": "accepted", "goal": 1, "x": -3.0, "y": 3.0, "yaw": 0.0},
             {"sim_s": 2.0, "x": -1.0, "y": 1.0, "yaw": 2.3, "path_m": 1.41},
             {"sim_s": 3.0, "x": -3.0, "y": 3.0, "yaw": 2.3, "path_m": 4.24},
             {"sim_s": 41.0, "event": "end", "path_m": 8.5}]
    (folder / "trace.jsonl").write_text("".join(json.dumps(r) + "\n" for r in trace)
                                        + '{"torn li')
    (folder / "reports.jsonl").write_text(json.dumps(
        {"survivor_id": "survivor_1", "frame_id": "map", "x": -2.5, "y": 3.2, "z": 0.0}) + "\n")


def test_layout_from_the_params_file() -> None:
    zones, base = mission_layout(PARAMS)
    assert [z["id"] for z in zones] == ["zone_a", "zone_b", "zone_c", "zone_d"]
    assert zones[1] == {"id": "zone_b", "x": 3.5, "y": 3.0, "yaw": 1.57}
    assert base == {"x": 0.0, "y": 0.0, "yaw": 0.0}


def test_summary_and_files(tmp_path: Path) -> None:
    _files(tmp_path)
    from sar_framework import load_spec

    inputs = MissionInputs(tmp_path, str(DEFAULT_TREE), str(PARAMS),
                           load_spec(DEFAULT_TREE), "SUCCESS", wall_duration_s=3.0)
    summary = summarise(inputs)
    assert [(z["id"], z["arrival_sim_s"]) for z in summary["zones_visited"]] == [
        ("zone_a", 18.0)]  # from the mission's start (sim_start_s 1.0)
    assert summary["zones_skipped"] == ["zone_b", "zone_c", "zone_d"]
    assert summary["base_reached"]["arrival_sim_s"] == 39.0
    assert summary["final_position"] == {"x": -3.0, "y": 3.0}
    assert summary["at_base"] is False
    assert [(s["id"], s["acknowledged"]) for s in summary["survivors"]] == [
        ("survivor_1", True), ("survivor_2", False)]
    assert summary["survivors"][1]["refused"] == "refuse_all is set"
    assert summary["path_length_m"] == 8.5 and summary["navigation_goals"] == 1
    assert summary["sim_duration_s"] == 40.0 and summary["ticks_per_wall_s"] == 40.0
    assert summary["real_time_factor"] == 20.0
    written = write_report(inputs)
    assert [p.name for p in written] == ["mission.json", "mission.png", "tree.svg"]
    assert (tmp_path / "mission.png").read_bytes()[:4] == b"\x89PNG"


def test_every_simulated_time_counts_from_the_first_tick(tmp_path: Path) -> None:
    """Regression: a failure 10 s after an arrival read 97.8 s later (two zero points)."""
    _files(tmp_path)
    _events(tmp_path,
            MissionEvent(SarKind.ZONE_REACHED, sim_s=19.0, fields={"zone_id": "zone_a"}),
            MissionEvent(SarKind.SURVIVOR_BROADCAST, sim_s=20.0,
                         fields={"survivor_id": "survivor_1"}, position=(-2.5, 3.2, 0.0)),
            MissionEvent(EventKind.FAILURE, sim_s=29.0, node_name="DetectSurvivor",
                         message="no answer"))
    summary = summarise(MissionInputs(tmp_path, str(DEFAULT_TREE), str(PARAMS), None,
                                      "FAILURE"))
    assert summary["sim_start_s"] == 1.0
    arrival = summary["zones_visited"][0]["arrival_sim_s"]
    assert (arrival, summary["survivors"][0]["found_sim_s"],
            summary["failures"][0]["sim_s"]) == (18.0, 19.0, 28.0)


def test_report_without_any_run_files(tmp_path: Path) -> None:
    inputs = MissionInputs(tmp_path, "t.yaml", str(tmp_path / "none.yaml"), None, "ERROR",
                           reason="the runner exited (3)")
    written = write_report(inputs)
    assert [p.name for p in written] == ["mission.json", "mission.png"]
    summary = json.loads((tmp_path / "mission.json").read_text())
    assert summary["goals"] == [] and summary["sim_duration_s"] is None
    assert "zones_visited" not in summary  # no zones, no event of the app: nothing of it


def test_a_label_near_the_map_edge_stays_out_of_the_legend() -> None:
    """Regression: "ne_corner (not reached)" ran into the legend panel of mission.png."""
    assert shift_into(700.0, 790.0, limit=768.0) == 22.0  # moved left by its overflow
    assert shift_into(100.0, 180.0, limit=768.0) == 0.0  # inside: left alone
    assert shift_into(10.0, 900.0, limit=768.0) == 10.0  # wider than the room: stop at 0


def _status(folder: Path, sim_start: float, base_at: float) -> None:
    (folder / "status.json").write_text(json.dumps({
        "status": "SUCCESS", "ticks": 10, "wall_first_tick_s": 0.5, "sim_start_s": sim_start,
        "sim_end_s": base_at, "wall_duration_s": 6.0, "nodes": {}, "events": [],
        "failures": []}))
    _events(folder, MissionEvent(SarKind.BASE_REACHED, sim_s=base_at, wall_s=5.0))


def test_base_arrival_is_within_the_simulated_duration(tmp_path: Path) -> None:
    """Regression: base arrival 104.7 s simulated in a mission of 102.6 s simulated."""
    _status(tmp_path, 2.1, 104.7)
    (tmp_path / "trace.jsonl").write_text(json.dumps(
        {"sim_s": 104.7, "x": 0.1, "y": -0.2, "yaw": 0.0, "path_m": 30.0}) + "\n")
    summary = summarise(MissionInputs(tmp_path, "t.yaml", str(PARAMS), None, "SUCCESS"))
    assert summary["sim_duration_s"] == 102.6
    assert summary["base_reached"]["arrival_sim_s"] == 102.6
    assert summary["final_position"] == {"x": 0.1, "y": -0.2} and summary["at_base"] is True


def _png(path: Path):
    from PIL import Image

    return Image.open(path).convert("RGB")


def test_a_long_tree_path_in_the_title_is_cut_at_the_left_not_at_the_image_edge(
        tmp_path: Path) -> None:
    """Regression: the absolute tree path pushed the title off the right edge of mission.png."""
    long_tree = "/home/someone/projects/" + "deeply/nested/" * 8 + "my_mission_tree.yaml"
    _status(tmp_path, 0.0, 10.0)
    write_report(MissionInputs(tmp_path, long_tree, str(PARAMS), None, "SUCCESS"))
    image = _png(tmp_path / "mission.png")
    band = image.crop((image.width - 12, 0, image.width, 40))
    assert [c for _, c in band.getcolors()] == [(255, 255, 255)]  # nothing at the right edge
    assert fit_left(long_tree, 100.0, lambda t: 7.0 * len(t)) == "…ion_tree.yaml"
    assert fit_left("short.yaml", 100.0, lambda t: 7.0 * len(t)) == "short.yaml"


def test_an_injected_blocked_area_is_drawn_and_listed(tmp_path: Path) -> None:
    """Regression: a blocked_areas fault was not drawn on mission.png."""
    _status(tmp_path, 0.0, 10.0)
    inputs = MissionInputs(tmp_path, "t.yaml", str(PARAMS), None, "SUCCESS",
                           blocked_areas=((3.5, 3.0, 0.6),))
    write_report(inputs)
    assert json.loads((tmp_path / "mission.json").read_text())["blocked_areas"] == [
        {"x": 3.5, "y": 3.0, "radius": 0.6}]
    counts = {c: n for n, c in _png(tmp_path / "mission.png").getcolors(maxcolors=1 << 20)}
    assert counts.get(BLOCKED_COLOUR, 0) > 100
