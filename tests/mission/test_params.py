"""Mission parameters: the file checker (pure Python) and the reader (real rclpy node)."""

from __future__ import annotations

import textwrap
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest
from sar_plugins.sar import params as mission_params
from sar_plugins.sar.zone_manager import ZoneManager

from sar_framework.mission.params_file import (
    ParamsError,
    check_params_file,
    params_files_from_args,
)

REPO = Path(__file__).resolve().parents[2]
MISSION_PARAMS = REPO / "config" / "mission_params.yaml"

SPEC_ZONES = [
    {"id": "zone_a", "x": -3.0, "y": 3.0, "yaw": 0.0},
    {"id": "zone_b", "x": 3.5, "y": 3.0, "yaw": 1.57},
    {"id": "zone_c", "x": 4.0, "y": -3.0, "yaw": 3.14},
    {"id": "zone_d", "x": -3.5, "y": -3.0, "yaw": -1.57},
]

#: The example of the module docstring (so the docs show a file that passes).
GOOD = textwrap.dedent(mission_params.__doc__.split("::\n\n")[1].split("\n\n")[0]) + "\n"


def write(tmp_path: Path, text: str, name: str = "params.yaml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


# --- the file checker (no ROS) -------------------------------------------------------------

def test_spec_file_passes_the_checker_and_locates_keys():
    keys = check_params_file(MISSION_PARAMS)
    assert set(keys) >= {"zone_order", "zones.zone_a.x", "zones.zone_d.yaw",
                         "base_station.yaw", "tick_rate_hz"}
    assert keys["zone_order"].line == 3
    assert keys["zones.zone_c.x"].line == 7


def test_spec_file_is_exactly_the_spec():
    import yaml

    doc = yaml.safe_load(MISSION_PARAMS.read_text())
    params = doc["/**"]["ros__parameters"]
    assert params["zone_order"] == ["zone_a", "zone_b", "zone_c", "zone_d"]
    assert params["zones"] == {z["id"]: {k: z[k] for k in ("x", "y", "yaw")} for z in SPEC_ZONES}
    assert params["base_station"] == {"x": 0.0, "y": 0.0, "yaw": 0.0}
    assert params["tick_rate_hz"] == 2.0


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("/**:\n  ros__parameters:\n    zone_order: [\"a\"\n",
         "params.yaml:4:1: YAML syntax error: while parsing a flow sequence: expected ','"),
        ("/**:\n  ros__parameters:\n    zone_order: []\n",
         "params.yaml:3:17: zone_order: empty list"),
        ("/**:\n  ros__parameters:\n    zone_order: [\"a\", 1]\n",
         "params.yaml:3:17: zone_order: a list must hold one type, got integer and string"),
        ("/**:\n  ros__parameters:\n    tick_rate_hz:\n",
         "params.yaml:3:18: tick_rate_hz: no value (null)"),
        ("/**:\n  tick_rate_hz: 2.0\n",
         "params.yaml:2:17: /**/tick_rate_hz: expected a mapping holding 'ros__parameters'"),
        ("/**:\n  ros__parameters:\n    a: 1\n    a: 2\n",
         "params.yaml:4:5: a: duplicate key (first set on line 3)"),
        ("/**:\n  ros__parameters:\n    zones: {z: {x: [[1]]}}\n",
         "params.yaml:3:21: zones.z.x: a list may only hold plain values"),
        ("", "params.yaml: empty file"),
        ("just text\n", "params.yaml:1:1: expected a mapping holding 'ros__parameters'"),
    ],
)
def test_checker_reports_file_line_and_key(tmp_path, monkeypatch, text, expected):
    monkeypatch.chdir(tmp_path)
    write(tmp_path, text)
    with pytest.raises(ParamsError) as err:
        check_params_file("params.yaml")
    assert str(err.value).startswith(expected), str(err.value)
    assert "\n" not in str(err.value)


def test_checker_missing_file(tmp_path):
    with pytest.raises(ParamsError, match=r"nope\.yaml: file not found"):
        check_params_file(tmp_path / "nope.yaml")


def test_params_files_from_args():
    argv = ["runner", "--flag", "--ros-args", "-p", "a:=1", "--params-file", "one.yaml",
            "--params-file", "two.yaml", "--", "--params-file", "not_ros.yaml"]
    assert params_files_from_args(argv) == ["one.yaml", "two.yaml"]
    assert params_files_from_args(["runner", "--params-file", "x.yaml"]) == []


# --- the reader (real rclpy node) ----------------------------------------------------------

@contextmanager
def params_node(*params_files: Path, overrides: tuple[str, ...] = ()) -> Iterator[object]:
    import rclpy
    from rclpy.context import Context

    from sar_framework.mission.params import create_params_node

    args = ["test", "--ros-args"]
    for file in params_files:
        args += ["--params-file", str(file)]
    for override in overrides:
        args += ["-p", override]
    context = Context()
    rclpy.init(args=args, context=context)
    node = create_params_node("params_test", context=context)
    try:
        yield node
    finally:
        node.destroy_node()
        rclpy.shutdown(context=context)


def read(path: Path, *, overrides: tuple[str, ...] = ()):
    from sar_plugins.sar.params import read_mission_params

    locations = check_params_file(path)
    with params_node(path, overrides=overrides) as node:
        return read_mission_params(node, source=str(path), locations=locations)


@pytest.mark.ros
def test_spec_file_gives_the_spec_zone_manager():
    mission = read(MISSION_PARAMS)
    expected = ZoneManager(SPEC_ZONES, {"x": 0.0, "y": 0.0, "yaw": 0.0})
    zm = mission.zone_manager
    assert mission.tick_rate_hz == 2.0
    assert mission.zone_order == ("zone_a", "zone_b", "zone_c", "zone_d")
    assert mission.unused_zones == ()
    assert zm.total_zones() == expected.total_zones() == 4
    assert zm.base_pose() == expected.base_pose()
    while expected.has_remaining():
        assert zm.current_zone() == expected.current_zone()
        zm.advance()
        expected.advance()
    assert not zm.has_remaining()


@pytest.mark.ros
def test_defaults_and_integers_and_unused_zones(tmp_path):
    path = write(tmp_path, "/**:\n  ros__parameters:\n    zone_order: [\"q\"]\n    zones:\n"
                 "      q: {x: 1, y: -2, yaw: 0}\n      spare: {x: 0.0, y: 0.0, yaw: 0.0}\n")
    mission = read(path)
    assert mission.tick_rate_hz == 2.0  # declared default (guarded by has_parameter)
    assert mission.zone_manager.base_pose() == {"x": 0.0, "y": 0.0, "yaw": 0.0}
    assert mission.zone_manager.current_zone() == {"id": "q", "x": 1.0, "y": -2.0, "yaw": 0.0}
    assert mission.unused_zones == ("spare",)


@pytest.mark.ros
def test_command_line_override_wins(tmp_path):
    path = write(tmp_path, GOOD)
    assert read(path, overrides=("tick_rate_hz:=5.0",)).tick_rate_hz == 5.0


@pytest.mark.ros
@pytest.mark.parametrize(
    ("old", "new", "expected"),
    [
        ('zone_order: ["zone_a", "zone_b"]', 'zone_order: ["zone_a", "zone_e"]',
         "{file}: zones.zone_e.x: missing (zone_e is in zone_order)"),
        ("zone_a: {x: -3.0,", 'zone_a: {x: "abc",',
         "{file}:5: zones.zone_a.x: must be a number, got 'abc'"),
        ("zone_b: {x: 3.5, y: 3.0, yaw: 1.57}", "zone_b: {x: 3.5, y: 3.0, yaw: true}",
         "{file}:6: zones.zone_b.yaw: must be a number, got True"),
        ("zone_a: {x: -3.0,", "zone_a: {x: .nan,",
         "{file}:5: zones.zone_a.x: must be finite, got nan"),
        ("tick_rate_hz: 2.0", "tick_rate_hz: 0.0", "{file}:8: tick_rate_hz: must be > 0, got 0.0"),
        ("tick_rate_hz: 2.0", "tick_rate_hz: -1", "{file}:8: tick_rate_hz: must be > 0, got -1"),
        ('zone_order: ["zone_a", "zone_b"]', 'zone_order: ["zone_a", "zone_a"]',
         "{file}:3: zone_order: zone_a is listed twice"),
        ('zone_order: ["zone_a", "zone_b"]', 'zone_order: zone_a',
         "{file}:3: zone_order: must be a list of zone ids (strings), got 'zone_a'"),
        ('zone_order: ["zone_a", "zone_b"]', 'zone_order: [""]',
         "{file}:3: zone_order: entry 0 is an empty zone id"),
        ('    zone_order: ["zone_a", "zone_b"]\n', "",
         "{file}: zone_order: missing (list the zone ids to visit, in order)"),
        ("base_station: {x: 0.0,", 'base_station: {x: "home",',
         "{file}:7: base_station.x: must be a number, got 'home'"),
    ],
)
def test_malformed_mission_gives_one_clear_message(tmp_path, old, new, expected):
    from sar_framework.mission.params import ParamsError as Reexported

    assert old in GOOD
    path = write(tmp_path, GOOD.replace(old, new))
    with pytest.raises(Reexported) as err:
        read(path)
    assert str(err.value) == expected.format(file=path)


@pytest.mark.ros
def test_declared_keys_are_not_redeclared(tmp_path):
    """A second read on the same node must not raise ParameterAlreadyDeclaredException."""
    from sar_plugins.sar.params import read_mission_params

    path = write(tmp_path, "/**:\n  ros__parameters:\n    zone_order: [\"q\"]\n"
                 "    zones: {q: {x: 1.0, y: 2.0, yaw: 0.0}}\n")
    with params_node(path) as node:
        first = read_mission_params(node, source=str(path))
        second = read_mission_params(node, source=str(path))
    assert first.tick_rate_hz == second.tick_rate_hz == 2.0


@pytest.mark.ros
def test_runner_stops_on_a_malformed_mission_with_one_line_and_no_traceback(tmp_path,
                                                                              monkeypatch):
    from sar_testing.processes import NodeProcess

    monkeypatch.chdir(tmp_path)
    write(tmp_path, GOOD.replace('["zone_a", "zone_b"]', '["zone_a", "zone_e"]'),
          "mission_params.yaml")
    runner = NodeProcess(["-m", "sar_framework.runner.node", "--ros-args", "--params-file",
                          "mission_params.yaml", "-p", "seed_amcl:=false"], "runner",
                         log_dir=tmp_path).start()
    assert runner.wait(timeout=30) == 2
    errors = [line for line in runner.output.splitlines() if "ERROR" in line]
    assert len(errors) == 1, runner.output
    assert errors[0].endswith(
        "mission_params.yaml: zones.zone_e.x: missing (zone_e is in zone_order)")
    assert "Traceback" not in runner.output
