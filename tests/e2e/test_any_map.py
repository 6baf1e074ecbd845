"""The simulator on a map of the user's own: ``sar-tree run --map --spawn`` and ``map:=``.

The map is made here, as ``map_saver_cli`` would write it: a PGM and its yaml in a temporary
folder. A room of 6 m x 4 m with a wall across its middle, open at the north: the robot
starts west of the wall and drives around it to the east. Bad maps and spawn poses are
refused before anything starts, naming the file and the field.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from sar_testing.temp_dirs import launch_env

from sar_framework.cli import main
from sar_framework.orchestrate.inputs import check_inputs
from sar_framework.orchestrate.options import RunConfig
from sar_framework.report_map import MAP_YAML
from sar_framework.sim.occupancy import load_map

from .helpers import DEFAULT_TREE
from .test_any_mission import ROS2, WAYPOINT, ros_env

RESOLUTION = 0.05
ORIGIN = (-1.0, -1.0)
SIZE_M = (6.0, 4.0)
SPAWN = "0.0,0.0,1.57"
GOAL = (4.0, 0.0)
TREE = f"""\
format: 1
name: around_the_wall
plugins: [waypoint.py]
blackboard:
  goal: {{type: geometry_msgs/msg/PoseStamped, description: where to go}}
root:
  sequence:
    name: Cross
    memory: true
    children:
      - Waypoint: {{name: East, x: {GOAL[0]}, y: {GOAL[1]}, pose: "{{goal}}"}}
      - NavigateToPose: {{name: GoEast, goal: "{{goal}}", server_timeout: 1000}}
"""
# Outer safety bound of a whole run (about 10 s of wall time on an idle machine).
RUN_BOUND_S = 300


def write_map(folder: Path, **fields: object) -> Path:
    """A room with a wall from its south side to 1 m short of its north side, as map_saver
    writes it (trinary PGM: 0 occupied, 254 free, 205 unknown; row 0 the north edge)."""
    width, height = (round(s / RESOLUTION) for s in SIZE_M)
    pixels = np.full((height, width), 254, dtype=np.uint8)
    pixels[:2, :] = pixels[-2:, :] = pixels[:, :2] = pixels[:, -2:] = 0  # outer walls
    wall_col = round((2.0 - ORIGIN[0]) / RESOLUTION)
    pixels[round(1.0 / RESOLUTION):, wall_col:wall_col + 3] = 0  # from the south up to y = 2
    folder.mkdir(parents=True, exist_ok=True)
    Image.fromarray(pixels).save(folder / "room.pgm")
    doc = {"image": "room.pgm", "mode": "trinary", "resolution": RESOLUTION,
           "origin": f"[{ORIGIN[0]}, {ORIGIN[1]}, 0.0]", "negate": 0,
           "occupied_thresh": 0.65, "free_thresh": 0.25, **fields}
    text = "".join(f"{key}: {value}\n" for key, value in doc.items() if value is not None)
    (folder / "room.yaml").write_text(text, encoding="utf-8")
    return folder / "room.yaml"


def test_the_map_made_here_reads_as_map_server_reads_it(tmp_path: Path) -> None:
    grid = load_map(write_map(tmp_path))
    assert (grid.width, grid.height, grid.origin_x, grid.origin_y) == (120, 80, -1.0, -1.0)
    assert grid.value_at(0.0, 0.0) == 0 and grid.value_at(2.05, 0.0) == 100
    assert grid.value_at(2.05, 2.5) == 0  # the way round, north of the wall


def _problems(tmp_path: Path, **options: object) -> list[str]:
    config = RunConfig(tree=str(DEFAULT_TREE), report_dir=str(tmp_path / "r"), **options)
    inputs, problems = check_inputs(config)
    assert inputs is None or not problems
    return problems


@pytest.mark.parametrize(("fields", "expected"), [
    ({"resolution": "fine"}, "room.yaml: resolution: expected a finite number, got 'fine'"),
    ({"origin": "[0, 0]"}, "room.yaml: origin: expected [x, y, yaw] numbers, got [0, 0]"),
    ({"image": "elsewhere.pgm"}, "room.yaml: image: cannot read "),
    ({"image": None}, "room.yaml: image: missing key"),
    ({"negate": 3}, "room.yaml: negate: expected 0 or 1, got 3"),
    ({"mode": "colour"}, "room.yaml: mode: expected trinary, scale or raw, got 'colour'"),
    ({"free_thresh": 0.9}, "room.yaml: free_thresh: expected below occupied_thresh"),
])
def test_a_bad_map_is_refused_before_the_run_naming_file_and_field(
        tmp_path: Path, fields: dict[str, object], expected: str) -> None:
    room = write_map(tmp_path / "map", **fields)
    problems = _problems(tmp_path, map=str(room))
    assert len(problems) == 1 and problems[0].startswith(f"--map: {room.absolute()}: "), problems
    assert expected in problems[0]


def test_a_spawn_pose_off_the_maps_free_space_is_refused(tmp_path: Path) -> None:
    room = str(write_map(tmp_path / "map"))
    assert _problems(tmp_path, map=room, spawn=(0.0, 0.0, 0.0)) == []
    assert _problems(tmp_path, map=room, spawn=(2.05, 0.0, 0.0)) == [
        f"--spawn: (2.05, 0) is not free on the map (occupied) on {Path(room).absolute()}"]
    outside = _problems(tmp_path, map=room, spawn=(9.0, 0.0, 0.0))
    assert outside == [f"--spawn: (9, 0) lies outside the map (x -1..5, y -1..3) on "
                       f"{Path(room).absolute()}"]
    # the course map's default spawn would be fine, but not on this map's wall either
    assert _problems(tmp_path, sim_params=["spawn_x:=0.0", "spawn_y:=5.0"]) == [
        "--sim-param spawn_x, spawn_y: (0, 5) is not free on the map (occupied) on "
        f"{MAP_YAML}"]


@pytest.mark.parametrize("text", ["1", "1,2,3,4", "east,2", "nan,0"])
def test_a_malformed_spawn_is_a_usage_error(capsys: pytest.CaptureFixture[str],
                                            text: str) -> None:
    # The command line's own entry point, in this process (``python -m sar_framework`` exits
    # with what it returns): argparse refuses the value before anything starts.
    assert main(["run", "t.yaml", "--spawn", text]) == 2
    stderr = capsys.readouterr().err
    assert f"argument --spawn: {text!r}: expected X,Y[,YAW] (metres, metres, radians)" \
        in stderr
    assert "Traceback" not in stderr


def own_folder(root: Path) -> Path:
    """A folder with the tree, its leaf and the map, nothing else."""
    folder = root / "mine"
    write_map(folder)
    (folder / "around.yaml").write_text(TREE, encoding="utf-8")
    (folder / "waypoint.py").write_text(WAYPOINT, encoding="utf-8")
    return folder


def assert_it_drove_round_the_wall_on_the_map_made_here(out: Path) -> None:
    report = json.loads((out / "mission.json").read_text(encoding="utf-8"))
    assert report["outcome"] == "SUCCESS", report
    assert [(g["node"], g["result"]) for g in report["goals"]] == [("GoEast", "reached")]
    final = report["final_position"]
    assert abs(final["x"] - GOAL[0]) < 0.3 and abs(final["y"] - GOAL[1]) < 0.3
    assert report["path_length_m"] > 2 * (2.0 - 0.0)  # up past the wall's end and down again
    trace = [json.loads(line) for line in (out / "trace.jsonl").read_text().splitlines()]
    start = next(r for r in trace if r.get("event") == "start")
    assert (start["x"], start["y"], round(start["yaw"], 2)) == (0.0, 0.0, 1.57)
    assert max(r["y"] for r in trace if "event" not in r) > 1.0  # round the north end
    assert_mission_png_is_the_map_made_here(out)


def assert_mission_png_is_the_map_made_here(out: Path) -> None:
    # mission.png is this map: 3 px a cell, a 44 px title strip, the legend 250 px wide
    with Image.open(out / "mission.png") as png:
        assert png.size == (120 * 3 + 250, max(80 * 3 + 44, 420))
        wall = png.getpixel((int((2.05 - ORIGIN[0]) / RESOLUTION * 3), 44 + 3 * 70))
        free = png.getpixel((int((4.5 - ORIGIN[0]) / RESOLUTION * 3), 44 + 3 * 70))
    assert wall == (55, 60, 68) and free == (250, 250, 247)


@pytest.mark.slow
@pytest.mark.ros
def test_sar_tree_run_drives_on_the_users_map_from_the_spawn_given(tmp_path: Path) -> None:
    folder = own_folder(tmp_path)
    done = subprocess.run([sys.executable, "-m", "sar_framework", "run", "around.yaml",
                           "--map", "room.yaml", "--spawn", SPAWN,
                           "--no-detect-server", "--no-report-server",  # the tree calls none
                           "--report-dir", "out",
                           "--record", "out/around.mcap"],
                          cwd=folder, capture_output=True, text=True,
                          env=ros_env(tmp_path / "ros_log"), timeout=RUN_BOUND_S, check=False)
    assert done.returncode == 0, done.stdout + done.stderr
    assert_it_drove_round_the_wall_on_the_map_made_here(folder / "out")
    # the recording keeps the map: its replay draws the same
    again = tmp_path / "again"
    done = subprocess.run([sys.executable, "-m", "sar_framework", "replay",
                           str(folder / "out" / "around.mcap"), "--report-dir", str(again)],
                          capture_output=True, text=True, timeout=RUN_BOUND_S, check=False)
    assert done.returncode == 0, done.stdout + done.stderr
    replayed, made = load_map(again / "map.yaml"), load_map(folder / "room.yaml")
    assert replayed.data.tolist() == made.data.tolist()
    assert (replayed.origin_x, replayed.origin_y) == (made.origin_x, made.origin_y)
    assert_mission_png_is_the_map_made_here(again)
    # and the studio's replay shows it
    from sar_framework.studio.session import replay_session

    world = replay_session(folder / "out" / "around.mcap", tmp_path / "sources").world
    assert (world["grid"]["width"], world["grid"]["height"]) == (120, 80)
    assert world["grid"]["origin"] == [-1.0, -1.0]


@pytest.mark.slow
@pytest.mark.ros
def test_ros2_launch_takes_the_map_and_spawn_as_arguments(tmp_path: Path) -> None:
    if not ROS2.exists():
        pytest.skip("real-stack tier: ros2cli / launch not built")
    folder = own_folder(tmp_path)
    out = tmp_path / "out"
    done = subprocess.run([str(ROS2), "launch", "sar_framework", "search_and_rescue.launch.py",
                           "nav2:=embedded", "tree:=around.yaml", "map:=room.yaml",
                           f"spawn:={SPAWN}", f"report_dir:={out}"],
                          cwd=folder, capture_output=True, text=True, stdin=subprocess.DEVNULL,
                          env=launch_env(tmp_path, ros_env(tmp_path / "ros_log")),
                          timeout=RUN_BOUND_S, check=False)
    assert done.returncode == 0, done.stdout + done.stderr
    assert_it_drove_round_the_wall_on_the_map_made_here(out)


@pytest.mark.slow
@pytest.mark.ros
def test_ros2_launch_refuses_a_bad_map_naming_file_and_field(tmp_path: Path) -> None:
    if not ROS2.exists():
        pytest.skip("real-stack tier: ros2cli / launch not built")
    room = write_map(tmp_path / "map", resolution=-0.05)
    done = subprocess.run([str(ROS2), "launch", "sar_framework", "search_and_rescue.launch.py",
                           "nav2:=embedded", f"map:={room}", f"report_dir:={tmp_path / 'out'}"],
                          cwd=tmp_path, capture_output=True, text=True, stdin=subprocess.DEVNULL,
                          env=launch_env(tmp_path, ros_env(tmp_path / "ros_log")),
                          timeout=RUN_BOUND_S, check=False)
    assert done.returncode != 0
    assert f"map:={room}: {room}: resolution: expected a positive number, got -0.05" \
        in done.stdout + done.stderr


def test_a_fleets_picture_is_drawn_on_the_map_its_robots_drove_on(tmp_path: Path) -> None:
    from sar_framework.report_robots import draw_fleet

    room = write_map(tmp_path / "map")
    for name, x in (("robot1", 0.0), ("robot2", 4.0)):
        (tmp_path / name).mkdir()
        (tmp_path / name / "trace.jsonl").write_text(
            json.dumps({"sim_s": 0.0, "event": "start", "x": x, "y": 0.0, "yaw": 0.0,
                        "map": str(room)}) + "\n", encoding="utf-8")
    fleet = {"robots": {"robot1": {}, "robot2": {}}, "outcome": "SUCCESS"}
    out = draw_fleet(tmp_path, fleet, [], tmp_path / "fleet.png")
    with Image.open(out) as png:
        assert png.size[0] == 120 * 3 + 420  # this map's 120 cells, then the legend
        assert png.getpixel((int((2.05 - ORIGIN[0]) / RESOLUTION * 3), 44 + 3 * 70)) == \
            (55, 60, 68)
