"""The fleet file: robots and spawn poses, every problem at its file:line:col."""

from __future__ import annotations

from pathlib import Path

import pytest

from sar_framework.sim.fleet_file import FleetFileError, load_fleet
from sar_framework.sim.world import Pose2D

GOOD = """\
robots:
  - name: robot1
    pose: {x: -1.0, y: 0.5, yaw: 1.5}
  - name: robot_2
    pose: {x: 2, y: 0.5}
"""


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "fleet.yaml"
    path.write_text(text, encoding="utf-8")
    return path


def problems(tmp_path: Path, text: str) -> list[str]:
    path = write(tmp_path, text)
    with pytest.raises(FleetFileError) as caught:
        load_fleet(path)
    prefix = f"{path}:"
    lines = str(caught.value).splitlines()
    assert all(line.startswith(prefix) for line in lines), lines
    return [line[len(prefix):] for line in lines]


def test_a_good_file_gives_names_and_spawns_in_order(tmp_path: Path) -> None:
    robots = load_fleet(write(tmp_path, GOOD))
    assert [(r.name, r.spawn) for r in robots] == [
        ("robot1", Pose2D(-1.0, 0.5, 1.5)), ("robot_2", Pose2D(2.0, 0.5, 0.0))]
    assert (robots[1].where.line, robots[1].where.col) == (4, 5)


@pytest.mark.parametrize(("text", "expected"), [
    ("", ["1:1: empty fleet file: expected 'robots:' with a list"]),
    ("robots: []\n", ["1:9: robots: expected a non-empty list of {name, pose}"]),
    ("robot: []\n", ["1:1: <top level>.robot: unknown key (allowed: robots)",
                     "1:1: missing key 'robots'"]),
    ("robots:\n  - name: robot1\n", ["2:5: robots[0]: missing key 'pose'"]),
    ("robots:\n  - name: 1robot\n    pose: {x: 0, y: 0}\n",
     ["2:11: robots[0].name: expected a namespace name (a letter, then letters, digits or "
      "'_'), got '1robot'"]),
    ("robots:\n  - name: a\n    pose: {x: 0, y: 0}\n  - name: a\n    pose: {x: 1, y: 0}\n",
     ["4:11: robots[1].name: robot 'a' already named on line 2"]),
    ("robots:\n  - name: a\n    pose: {x: zero, y: 0, z: 1}\n",
     ["3:27: robots[0].pose.z: unknown key (allowed: x, y, yaw)",
      "3:15: robots[0].pose.x: expected a finite number, got 'zero'"]),
    ("robots:\n  - name: a\n    pose: {y: .nan}\n",
     ["3:11: robots[0].pose: missing key 'x'",
      "3:15: robots[0].pose.y: expected a finite number, got '.nan'"]),
    ("robots:\n  - name: a\n    pose: {x: 0, y: 0}\n    colour: red\n",
     ["4:5: robots[0].colour: unknown key (allowed: name, pose)"]),
    ("robots:\n  - [a]\n", ["2:5: robots[0]: expected a mapping with name, pose"]),
    ("robots:\n  - name: a\n    pose: {x: 0, y: 0\n",
     None),  # a YAML syntax error: reported by the shared YAML reader, at its line
])
def test_bad_files_name_file_line_and_column(tmp_path: Path, text: str,
                                             expected: list[str] | None) -> None:
    found = problems(tmp_path, text)
    if expected is None:
        assert found and found[0].split(":")[0].isdigit()
    else:
        assert found == expected


def test_a_missing_file_is_an_error_not_a_traceback(tmp_path: Path) -> None:
    with pytest.raises(FleetFileError, match=r"nope\.yaml:1:1: no such file"):
        load_fleet(tmp_path / "nope.yaml")


@pytest.mark.ros
@pytest.mark.parametrize(("text", "expected"), [
    ("robots:\n  - name: a\n    pose: {x: 0, y: zero}\n",
     ":3:21: robots[0].pose.y: expected a finite number, got 'zero'"),
    ("robots:\n  - name: a\n    pose: {x: 0, y: 0}\n  - name: b\n    pose: {x: 0.3, y: 0}\n",
     ":4:5: robot 'b' spawns within 0.44 m (two footprints) of robot 'a' ("),
])
def test_the_simulator_refuses_a_bad_fleet_file_with_its_line(tmp_path: Path, text: str,
                                                              expected: str) -> None:
    import subprocess
    import sys

    path = write(tmp_path, text)
    result = subprocess.run(
        [sys.executable, "-m", "sar_framework.sim", "--ros-args", "-p",
         f"fleet_file:={path}"], capture_output=True, text=True, timeout=60, check=False)
    output = result.stdout + result.stderr
    assert result.returncode == 2, output
    assert f"{path}{expected}" in output
    assert "Traceback" not in output
