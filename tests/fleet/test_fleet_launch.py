"""``ros2 launch sar_framework fleet.launch.py`` starts what ``sar-tree run --robots`` starts.

The launch description is evaluated by launch itself (no process starts): the same
executables, in the same order and namespaces, with the same parameters as the command
lines of ``sar-tree run TREE --robots 3`` (one description:
:mod:`sar_framework.mission.processes`).
"""

from __future__ import annotations

import importlib.util
import itertools
from pathlib import Path

import pytest
import yaml

from sar_framework.orchestrate.config import check_config, child_specs
from sar_framework.orchestrate.options import RunConfig

REPO = Path(__file__).resolve().parents[2]
LAUNCH = REPO / "launch" / "fleet.launch.py"
TREE = REPO / "trees" / "fleet_search.yaml"
MISSION = REPO / "config" / "mission_params.yaml"
SURVIVORS = REPO / "config" / "survivors.yaml"

pytestmark = [
    pytest.mark.skipif(importlib.util.find_spec("launch_ros") is None,
                       reason="launch_ros is not built"),
    pytest.mark.usefixtures("launch_tmpdir"),  # launch's launch_params_* files in tmp_path
]


def _parameters(arguments: list[str]) -> dict:
    merged: dict = {}
    for flag, value in itertools.pairwise(arguments):
        if flag == "--params-file":
            for content in (yaml.safe_load(Path(value).read_text()) or {}).values():
                merged.update(content.get("ros__parameters", {}))
        elif flag == "-p":
            name, _, text = value.partition(":=")
            merged[name] = yaml.safe_load(text)
    return merged


def launched(**arguments: str) -> list[tuple[str, str, dict]]:
    """``(namespace, executable, parameters)`` of each Node the launch would start."""
    from launch.actions import IncludeLaunchDescription
    from launch.launch_description_sources import PythonLaunchDescriptionSource
    from launch.utilities import perform_substitutions
    from launch_ros.actions import Node

    from launch import LaunchContext, LaunchDescription

    context = LaunchContext()
    nodes: list = []

    def walk(entities: list) -> None:
        for entity in entities:
            if isinstance(entity, Node):
                entity._perform_substitutions(context)  # what Node.execute does first
                nodes.append(entity)
            elif isinstance(entity, LaunchDescription):
                walk(entity.entities)
            else:
                walk(entity.visit(context) or [])

    source = PythonLaunchDescriptionSource(str(LAUNCH))
    walk([IncludeLaunchDescription(source, launch_arguments=list(arguments.items()))])
    found = []
    for node in nodes:
        context.extend_locals({"ros_specific_arguments": {"ns": "__ns:=/"}})
        command = [perform_substitutions(context, part) for part in node.cmd[1:]]
        namespace = node.expanded_node_namespace
        namespace = "" if namespace == Node.UNSPECIFIED_NODE_NAMESPACE else namespace.strip("/")
        found.append((namespace, node.node_executable, _parameters(command)))
    return found


def test_the_launch_and_sar_tree_run_start_the_same_fleet(tmp_path: Path) -> None:
    launch = launched(robots="3", tree=str(TREE), params_file=str(MISSION),
                      survivors_file=str(SURVIVORS), report_dir=str(tmp_path), speed="7.5")
    config = RunConfig(tree=str(TREE), params=str(MISSION), robots=3, speed=7.5,
                       app_options={"--survivors": str(SURVIVORS)})
    inputs = check_config(config)
    run = []
    for spec in child_specs(config, tmp_path, inputs.places, apps=inputs.apps,
                            robots=inputs.robots, node_kinds=inputs.node_kinds):
        namespace = spec.label.rpartition("/")[0]
        run.append((namespace, spec.executable, _parameters(list(spec.ros_args))))
    assert [(ns, exe) for ns, exe, _ in launch] == [(ns, exe) for ns, exe, _ in run] == [
        ("", "sar-sim"), ("", "sar-report-survivor-server"), ("", "sar-zone-coordinator"),
        ("robot1", "sar-detect-survivor-server"), ("robot2", "sar-detect-survivor-server"),
        ("robot3", "sar-detect-survivor-server"), ("robot1", "sar-mission-runner"),
        ("robot2", "sar-mission-runner"), ("robot3", "sar-mission-runner")]
    for (_, executable, by_launch), (_, _, by_run) in zip(launch, run, strict=True):
        # sar-tree run keeps the runner's exit for itself; the launch ends on the runners
        assert by_launch == by_run, executable
    assert (tmp_path / "fleet.yaml").is_file()  # robots:=3 wrote the fleet file


def test_a_fleet_file_names_the_launch_s_robots(tmp_path: Path) -> None:
    fleet = tmp_path / "fleet.yaml"
    fleet.write_text("robots:\n  - name: scout\n    pose: {x: -3.0, y: -1.0, yaw: 1.5}\n")
    launch = launched(fleet_file=str(fleet), tree=str(REPO / "trees" / "search_and_rescue.yaml"),
                      report_dir=str(tmp_path / "run"))
    assert [(ns, exe) for ns, exe, _ in launch] == [
        ("", "sar-sim"), ("", "sar-report-survivor-server"),
        ("scout", "sar-detect-survivor-server"), ("scout", "sar-mission-runner")]
    runner = launch[-1][2]
    assert (runner["initial_pose.yaw"], runner["base_station.x"]) == (1.5, -3.0)
    assert launch[0][2]["fleet_file"] == str(fleet)
