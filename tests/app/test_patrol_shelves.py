"""The inspection patrol's shelves as data: one file gives each shelf's scanning pose.

Its leaf ShelfGoal writes the pose of the shelf a ``LoopString`` names to ``goal``; a wrong
file or field is an error naming the file and the field; a shelf the data lacks fails the
leaf, saying which shelves there are. The scan server serves the shelves the same file names.
"""

from __future__ import annotations

import importlib.util
import math
import shutil
import subprocess
import sys
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest
from py_trees.common import Status

from sar_framework.mission.processes import MissionSettings

PACKAGE = Path(__file__).resolve().parents[2] / "examples" / "inspection_patrol" / \
    "inspection_patrol"


@pytest.fixture(scope="module")
def shelves() -> ModuleType:
    """The app's plugin file, imported by path as a tree's ``plugins:`` imports it."""
    spec = importlib.util.spec_from_file_location("patrol_shelves_under_test",
                                                  PACKAGE / "shelves.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


class Ports:
    """A leaf's ports over a dict (what the engine's binding offers: get and set)."""

    def __init__(self, **values: Any) -> None:
        self.values = dict(values)

    def get(self, name: str) -> Any:
        return self.values[name]

    def set(self, name: str, value: Any) -> None:
        self.values[name] = value


def test_the_shipped_data_names_each_shelf_and_its_pose(shelves: ModuleType) -> None:
    poses = shelves.load_shelves(shelves.SHELVES_FILE)
    assert list(poses) == ["A", "B", "C"]
    assert poses["C"] == (5.7, 2.0, 3.14)


@pytest.mark.parametrize(("text", "said"), [
    ("A: {x: 1.0, y: 2.0}\n", "shelf A: field 'yaw': missing"),
    ("A: {x: 1.0, y: 2.0, yaw: 0.0, z: 1.0}\n", "shelf A: field 'z': unknown"),
    ("A: {x: one, y: 2.0, yaw: 0.0}\n", "shelf A: field 'x': a number is needed, got 'one'"),
    ("A: {x: 1.0, y: true, yaw: 0.0}\n", "shelf A: field 'y': a number is needed, got True"),
    ("A: [1.0, 2.0, 0.0]\n", "shelf A: a pose {x, y, yaw} is needed"),
    ("shelf 1: {x: 1.0, y: 2.0, yaw: 0.0}\n", "shelf 'shelf 1': a name is needed"),
    ("- A\n- B\n", "a mapping of shelf names to poses is needed"),
    ("A: {x: [1.0\n", "cannot read the shelves"),
])
def test_bad_data_is_an_error_naming_the_file_and_the_field(
        shelves: ModuleType, tmp_path: Path, text: str, said: str) -> None:
    path = tmp_path / "shelves.yaml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(shelves.ShelfDataError) as raised:
        shelves.load_shelves(path)
    assert str(raised.value).startswith(f"{path}: "), raised.value
    assert said in str(raised.value)


def test_a_missing_file_is_named(shelves: ModuleType, tmp_path: Path) -> None:
    with pytest.raises(shelves.ShelfDataError, match="cannot read the shelves"):
        shelves.load_shelves(tmp_path / "nowhere.yaml")


def test_shelf_goal_writes_the_shelfs_pose_and_fails_on_an_unknown_shelf(
        shelves: ModuleType) -> None:
    leaf = shelves.ShelfGoal("ShelfPose", frame_id="map", ports=Ports(shelf="C"))
    leaf.setup()
    assert leaf.update() == Status.SUCCESS
    goal = leaf.ports.values["goal"]
    assert goal.header.frame_id == "map"
    assert (goal.pose.position.x, goal.pose.position.y) == (5.7, 2.0)
    assert math.isclose(2 * math.atan2(goal.pose.orientation.z, goal.pose.orientation.w), 3.14)
    leaf.ports.values.update(shelf="D", goal=None)
    assert leaf.update() == Status.FAILURE
    assert leaf.feedback_message == "shelves.yaml: no shelf 'D' (it has A, B, C)"
    assert leaf.ports.values["goal"] is None


def test_bad_data_stops_the_leaf_at_setup(shelves: ModuleType, tmp_path: Path,
                                          monkeypatch: pytest.MonkeyPatch) -> None:
    bad = tmp_path / "shelves.yaml"
    bad.write_text("A: {x: 1.0, y: 2.0, yaw: north}\n", encoding="utf-8")
    monkeypatch.setattr(shelves, "SHELVES_FILE", bad)
    leaf = shelves.ShelfGoal("ShelfPose", frame_id="map", ports=Ports(shelf="A"))
    with pytest.raises(shelves.ShelfDataError, match="shelf A: field 'yaw'"):
        leaf.setup()


def test_the_scan_server_serves_the_shelves_the_data_names(shelves: ModuleType) -> None:
    [scan] = shelves.APP.processes(MissionSettings(tree="patrol.yaml"))
    assert scan.parameters["shelves"] == ["A", "B", "C"]


def test_sar_tree_run_refuses_bad_data_before_it_starts(tmp_path: Path) -> None:
    folder = tmp_path / "inspection_patrol"
    shutil.copytree(PACKAGE.parent, folder,
                    ignore=shutil.ignore_patterns("__pycache__", "make_map.py"))
    data = folder / "inspection_patrol" / "shelves.yaml"
    data.write_text(data.read_text(encoding="utf-8").replace("yaw: 3.14", "yaw: west"),
                    encoding="utf-8")
    # Outer safety bound: the run stops at its checks, before any process starts.
    done = subprocess.run([sys.executable, "-m", "sar_framework", "run", "patrol.yaml",
                           "--map", "warehouse.yaml", "--report-dir", "out"], cwd=folder,
                          capture_output=True, text=True, timeout=120, check=False)
    assert done.returncode == 2, done.stdout + done.stderr
    assert f"error: {data}: shelf C: field 'yaw': a number is needed, got 'west'" in \
        done.stderr, done.stderr
    assert "Traceback" not in done.stderr
