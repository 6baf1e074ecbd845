"""Occupancy grid: known cells, map_server file format, loader, inflation, regeneration."""

import math
from collections import deque

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from PIL import Image
from sar_plugins.sar.course_world import load_course_world

from sar_framework.sim.map_writer import main, write_map
from sar_framework.sim.occupancy import (
    DEFAULT_MAP_PREFIX,
    FREE,
    OCCUPIED,
    UNKNOWN,
    MapError,
    OccupancyGrid,
    inflate,
    load_map,
    obstacle_distance,
    rasterize,
    reachable,
)

ZONES = {"zone_a": (-3.0, 3.0), "zone_b": (3.5, 3.0), "zone_c": (4.0, -3.0), "zone_d": (-3.5, -3.0)}
COMMITTED_PGM = DEFAULT_MAP_PREFIX.with_name("final_project_map.pgm")
COMMITTED_YAML = DEFAULT_MAP_PREFIX.with_name("final_project_map.yaml")


@pytest.fixture(scope="module")
def grid() -> OccupancyGrid:
    return rasterize(load_course_world().world)


def test_geometry_covers_arena_with_margin(grid):
    assert grid.resolution == 0.05
    assert (grid.origin_x, grid.origin_y) == (-6.4, -5.4)
    assert (grid.width, grid.height) == (256, 216)
    assert grid.data.dtype == np.int8


@pytest.mark.parametrize(
    "point",
    [
        (0.0, 5.0),
        (-5.9, 5.0),
        (5.9, -5.0),
        (6.0, 0.0),
        (-6.0, 4.9),  # outer walls
        (-3.0, 0.0),
        (-0.1, 0.0),
        (3.5, 0.0),
        (1.1, 0.0),  # horizontal inner walls
        (0.0, 3.25),
        (0.0, 1.6),
        (0.0, -3.25),
        (0.0, -1.6),  # vertical inner walls
        (-4.5, 3.8),
        (3.0, -3.0),
        (4.0, 2.5),
        (-2.0, -2.5),  # debris centres
        (-2.0, -2.22),
        (4.3, 2.85),
        (3.65, 2.15),  # cylinder rim, rotated box ends
    ],
)
def test_obstacles_occupied(grid, point):
    assert grid.value_at(*point) == OCCUPIED


@pytest.mark.parametrize(
    "point",
    [
        *ZONES.values(),
        (0.0, 0.0),  # base station
        (0.02, 0.0),
        (0.5, 0.0),
        (1.0, 0.0),  # the east-west doorway beside the base
        (0.0, 1.0),
        (0.0, -1.0),  # the north-south doorway
        (-2.5, 3.2),
        (4.1, -2.5),  # survivors
        (-2.0, -2.15),
        (3.3, 2.9),  # just beside debris
    ],
)
def test_free_space(grid, point):
    assert grid.value_at(*point) == FREE


def test_outside_the_arena_is_unknown(grid):
    assert grid.value_at(6.3, 0.0) == UNKNOWN  # inside the margin, beyond the east wall
    assert grid.value_at(0.0, -5.3) == UNKNOWN
    assert grid.value_at(50.0, 0.0) == UNKNOWN  # beyond the grid
    assert grid.data[0, 0] == UNKNOWN
    assert grid.data[-1, -1] == UNKNOWN
    # everything unknown is outside the outer walls' inner faces
    rows, cols = np.nonzero(grid.data == UNKNOWN)
    xs, ys = grid.cell_centres()
    assert np.all((np.abs(xs[cols]) > 5.9) | (np.abs(ys[rows]) > 4.9))


def test_world_to_cell_round_trip(grid):
    for row, col in [(0, 0), (10, 200), (215, 255)]:
        assert grid.world_to_cell(*grid.cell_to_world(row, col)) == (row, col)
    assert grid.world_to_cell(-6.4, -5.4) == (0, 0)
    assert not grid.in_bounds(-1, 0)


def test_yaml_is_map_server_format():
    assert COMMITTED_YAML.read_text().splitlines() == [
        "image: final_project_map.pgm",
        "mode: trinary",
        "resolution: 0.05",
        "origin: [-6.4, -5.4, 0.0]",
        "negate: 0",
        "occupied_thresh: 0.65",
        "free_thresh: 0.25",
    ]


def test_pgm_is_p5_trinary_with_top_row_at_max_y(grid):
    assert COMMITTED_PGM.read_bytes().startswith(b"P5\n")
    with Image.open(COMMITTED_PGM) as image:
        pixels = np.asarray(image)
    assert pixels.shape == (216, 256)
    assert set(np.unique(pixels)) == {0, 205, 254}
    # image row 0 is the top of the map: row for y = 5.0 (north wall) counted from the top
    row_from_top = grid.height - 1 - grid.world_to_cell(0.0, 5.0)[0]
    col = grid.world_to_cell(-5.0, 5.0)[1]
    assert pixels[row_from_top, col] == 0
    zone_a_row, zone_a_col = grid.world_to_cell(-3.0, 3.0)
    assert pixels[grid.height - 1 - zone_a_row, zone_a_col] == 254


def test_load_map_matches_map_server_reading(grid):
    loaded = load_map(COMMITTED_YAML)
    assert (loaded.resolution, loaded.origin_x, loaded.origin_y) == (0.05, -6.4, -5.4)
    assert np.array_equal(loaded.data == OCCUPIED, grid.data == OCCUPIED)
    known = grid.data != UNKNOWN
    assert np.array_equal(loaded.data[known], grid.data[known])
    # map_server with free_thresh 0.25 reads the unknown shade 205 as free (50/255 < 0.25)
    assert np.all(loaded.data[~known] == FREE)


def test_load_map_honours_thresholds_and_negate(tmp_path):
    Image.fromarray(np.array([[0, 100, 205, 254]], dtype=np.uint8)).save(tmp_path / "m.pgm")
    (tmp_path / "m.yaml").write_text(
        "image: m.pgm\nresolution: 0.1\norigin: [1, 2, 0]\nnegate: 0\n"
        "occupied_thresh: 0.65\nfree_thresh: 0.196\n"
    )
    loaded = load_map(tmp_path / "m.yaml")
    assert loaded.data.tolist() == [[OCCUPIED, UNKNOWN, UNKNOWN, FREE]]
    (tmp_path / "m.yaml").write_text(
        "image: m.pgm\nresolution: 0.1\norigin: [1, 2, 0]\nnegate: 1\n"
    )
    assert load_map(tmp_path / "m.yaml").data.tolist() == [[FREE, UNKNOWN, OCCUPIED, OCCUPIED]]


@pytest.mark.parametrize(
    ("text", "pattern"),
    [
        ("resolution: 0.05\norigin: [0, 0, 0]\n", r"m\.yaml: image: missing key"),
        ("image: m.pgm\norigin: [0, 0, 0]\n", r"m\.yaml: resolution: missing key"),
        ("image: m.pgm\nresolution: -1\norigin: [0, 0, 0]\n", r"resolution: expected a positive"),
        ("image: m.pgm\nresolution: 0.05\norigin: [0, 0]\n", r"m\.yaml: origin: expected \[x, y"),
        ("image: m.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nmode: fancy\n", r"mode: expected"),
        ("image: m.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 2\n", r"negate: expected"),
        ("image: gone.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n", r"m\.yaml: image: cannot read"),
        ("image: m.pgm\nresolution: 0.05\norigin: [0, 0, 0]\noccupied_thresh: 65\n",
         r"m\.yaml: occupied_thresh: expected a number from 0 to 1, got 65"),
        ("image: m.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nfree_thresh: 0.7\n",
         r"m\.yaml: free_thresh: expected below occupied_thresh \(0\.65\), got 0\.7"),
        ("image: m.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nfree_thresh: low\n",
         r"m\.yaml: free_thresh: expected a finite number, got 'low'"),
        ("[1, 2]\n", r"m\.yaml: expected a mapping"),
    ],
)
def test_load_map_errors_name_file_and_key(tmp_path, text, pattern):
    Image.fromarray(np.zeros((2, 2), dtype=np.uint8)).save(tmp_path / "m.pgm")
    (tmp_path / "m.yaml").write_text(text)
    with pytest.raises(MapError, match=pattern):
        load_map(tmp_path / "m.yaml")


def test_load_map_missing_yaml(tmp_path):
    with pytest.raises(MapError, match=r"none\.yaml: cannot read"):
        load_map(tmp_path / "none.yaml")


def test_write_is_deterministic(tmp_path, grid):
    a = write_map(grid, tmp_path / "a" / "m")
    b = write_map(rasterize(load_course_world().world), tmp_path / "b" / "m")
    for pa, pb in zip(a, b, strict=True):
        assert pa.read_bytes() == pb.read_bytes()


def test_inflation_by_footprint(grid):
    inflated = inflate(grid, 0.22)
    occupied = grid.data == OCCUPIED
    assert np.all(inflated[occupied])
    assert inflated.sum() > occupied.sum()
    assert 0.5 < (~inflated & (grid.data == FREE)).sum() / (grid.data == FREE).sum() < 0.95

    def at(x, y):
        return bool(inflated[grid.world_to_cell(x, y)])

    for x, y in ZONES.values():
        assert not at(x, y)
    assert at(0.0, 0.0)  # the base is 0.075 m from the end of wall_h_left
    assert at(-3.0, 0.2)  # 0.125 m from the wall face
    assert not at(-3.0, 0.4)
    assert not at(0.5, 0.0)  # the doorway stays open
    assert np.array_equal(inflate(grid, 0.0), occupied)


def test_unknown_command_line_world_fails(tmp_path, capsys):
    assert main(["--world", str(tmp_path / "x.yaml"), "--out", str(tmp_path / "m")]) == 1
    assert "x.yaml: cannot read world file" in capsys.readouterr().err


@settings(max_examples=30, deadline=None)
@given(
    cells=st.lists(st.tuples(st.integers(0, 19), st.integers(0, 24)), min_size=1, max_size=6),
    cap=st.floats(0.05, 0.6),
)
def test_obstacle_distance_matches_brute_force(cells, cap):
    occupied = np.zeros((20, 25), dtype=bool)
    for r, c in cells:
        occupied[r, c] = True
    dist = obstacle_distance(occupied, 0.05, cap)
    for r in range(20):
        for c in range(25):
            brute = min(math.hypot(r - rr, c - cc) * 0.05 for rr, cc in cells)
            assert dist[r, c] == pytest.approx(min(brute, cap), abs=1e-5)


def test_scale_mode_grades_between_the_thresholds_and_a_transparent_pixel_is_unknown(tmp_path):
    # shades 0 (black), 255 (white), 128 (between), 128 again but transparent
    pixels = np.array([[[0, 255], [255, 255], [128, 255], [128, 0]]], dtype=np.uint8)
    Image.fromarray(pixels, "LA").save(tmp_path / "m.png")
    (tmp_path / "m.yaml").write_text(
        "image: m.png\nmode: scale\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: 0\n"
        "occupied_thresh: 0.65\nfree_thresh: 0.25\n")
    between = round((1 - 128 / 255 - 0.25) / (0.65 - 0.25) * 100)
    assert load_map(tmp_path / "m.yaml").data.tolist() == [[OCCUPIED, FREE, between, UNKNOWN]]


def test_raw_mode_takes_the_pixel_as_the_occupancy(tmp_path):
    Image.fromarray(np.array([[0, 42, 100, 205]], dtype=np.uint8)).save(tmp_path / "m.pgm")
    (tmp_path / "m.yaml").write_text(
        "image: m.pgm\nmode: raw\nresolution: 0.1\norigin: [0, 0, 0]\n")
    assert load_map(tmp_path / "m.yaml").data.tolist() == [[0, 42, 100, UNKNOWN]]


def test_reachable_is_the_4_connected_region_of_the_seed() -> None:
    """The run-filling flood fill agrees with a plain breadth-first search on random grids."""
    rng = np.random.default_rng(7)
    for _ in range(200):
        height, width = (int(v) for v in rng.integers(1, 30, 2))
        passable = rng.random((height, width)) < rng.uniform(0.3, 0.8)
        seed = (int(rng.integers(height)), int(rng.integers(width)))
        expected = np.zeros_like(passable)
        queue = deque([seed] if passable[seed] else [])
        while queue:
            row, col = queue.popleft()
            if not (0 <= row < height and 0 <= col < width) or expected[row, col] \
                    or not passable[row, col]:
                continue
            expected[row, col] = True
            queue.extend([(row + 1, col), (row - 1, col), (row, col + 1), (row, col - 1)])
        assert np.array_equal(reachable(passable, seed), expected)
