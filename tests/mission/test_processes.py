"""The mission's one process description (sar_framework.mission.processes) and sar-tree run's use.

The launch file's side (the same description through launch's own machinery) is in
test_launch.py.
"""

from __future__ import annotations

import importlib
import os
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import pytest
import tomllib
from sar_plugins.sar.app import APP as SAR

from sar_framework.mission.processes import (
    MissionSettings,
    mission_processes,
    ros_arguments,
    ros_value,
)
from sar_framework.orchestrate.config import check_config, child_specs, mission_settings
from sar_framework.orchestrate.options import RunConfig

REPO = Path(__file__).resolve().parents[2]
TREE = REPO / "trees" / "search_and_rescue.yaml"
PARAMS = REPO / "config" / "mission_params.yaml"
PLUGINS = [str(REPO / "tests" / "mission" / "runner_plugins"), "sar_plugins"]
EVERYTHING = MissionSettings(tree=str(TREE), params_file=str(PARAMS), record="/tmp/m.mcap")


def test_the_description_imports_neither_ros_nor_launch() -> None:
    code = ("import sys, sar_framework.mission.processes\n"
            "print(sorted(m for m in sys.modules if m.split('.')[0] in ('rclpy', 'launch', "
            "'launch_ros', 'rcl_interfaces', 'ament_index_python', 'sar_framework.orchestrate')))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=False, timeout=60)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"


def test_processes_start_in_order_and_only_when_asked() -> None:
    assert [p.label for p in mission_processes(EVERYTHING, [SAR])] == [
        "recorder", "sim", "detect", "report", "runner"]
    assert [p.label for p in mission_processes(replace(
        EVERYTHING, record="", simulator=False, disabled=frozenset({"detect", "report"})),
        [SAR])] == ["runner"]


def test_a_tree_without_an_app_starts_no_servers_and_needs_no_parameter_file() -> None:
    settings = replace(EVERYTHING, params_file="")
    assert [p.label for p in mission_processes(settings)] == ["recorder", "sim", "runner"]
    assert mission_processes(settings)[-1].params_files == ()


@pytest.mark.parametrize("process", mission_processes(EVERYTHING, [SAR]),
                         ids=lambda p: p.label)
def test_each_executable_is_the_console_script_of_its_module(process) -> None:
    # What `ros2 launch` starts (lib/sar_framework/<executable>) and what sar-tree run starts
    # (python -m <module>) must be the same program.
    scripts = tomllib.loads((REPO / "pyproject.toml").read_text())["project"]["scripts"]
    entry_module, _, function = scripts[process.executable].partition(":")
    module = importlib.import_module(process.module)
    if hasattr(module, "__path__"):  # a package: -m runs its __main__
        module = importlib.import_module(process.module + ".__main__")
    assert getattr(module, function) is getattr(importlib.import_module(entry_module), function)


def test_unset_settings_leave_the_processes_their_own_defaults() -> None:
    by_label = {p.label: p for p in mission_processes(EVERYTHING, [SAR])}
    assert by_label["sim"].parameters == {}  # speed: the simulator's own default
    assert by_label["detect"].parameters == {"use_sim_time": True}
    assert by_label["report"].parameters == {"use_sim_time": True}
    assert by_label["runner"].params_files == (str(PARAMS),)
    assert by_label["runner"].parameters == {"tree": str(TREE), "use_sim_time": True,
                                             "exit_on_completion": True}
    assert by_label["recorder"].parameters == {
        "output": "/tmp/m.mcap", "tree": str(TREE), "params_file": str(PARAMS),
        "app_topics": [f"{name} {kind}" for name, kind in SAR.recorded_topics]}  # the app's
    assert "app_topics" not in mission_processes(EVERYTHING)[0].parameters  # no app, none


def test_the_recorder_gets_the_runners_plugin_paths_to_keep_their_sources() -> None:
    settings = replace(EVERYTHING, plugin_paths=("plugins/a.py", "more"))
    by_label = {p.label: p for p in mission_processes(settings)}
    assert by_label["recorder"].parameters["plugin_path"] == \
        by_label["runner"].parameters["plugin_path"] == f"plugins/a.py{os.pathsep}more"


def test_extra_parameters_are_set_last_and_override() -> None:
    settings = replace(EVERYTHING, use_sim_time=False, extra={
        "runner": {"use_sim_time": True, "completion": "once"}})
    runner = mission_processes(settings)[-1]
    assert runner.parameters["use_sim_time"] is True
    assert list(runner.parameters)[-1] == "completion"
    assert ros_arguments(runner)[:2] == ["--params-file", str(PARAMS)]


VALUES = [True, False, 0, -3, 20.0, 0.5, 1e-05, 2.5e20, "zone_a", "trees/a b.yaml", "true",
          "1.5", "12", "1:2:0.5", "a: b", "it's", "#hash", "", " padded ",
          ["1:2:0.5", "zone_b", "it's"], [1, 2], [0.5, 2.0], [True, False]]


@pytest.mark.ros
def test_rcl_reads_every_formatted_value_back_as_it_was() -> None:
    import rclpy
    from rclpy.context import Context
    from rclpy.node import Node

    arguments = ["--ros-args"]
    for index, value in enumerate(VALUES):
        arguments += ["-p", f"v{index}:={ros_value(value)}"]
    context = Context()
    rclpy.init(context=context)
    try:
        node = Node("values", context=context, cli_args=arguments,
                    automatically_declare_parameters_from_overrides=True)
        read = [node.get_parameter(f"v{index}").value for index in range(len(VALUES))]
        node.destroy_node()
    finally:
        rclpy.shutdown(context=context)
    for value, back in zip(VALUES, read, strict=True):
        got = back if isinstance(back, str | bool | int | float) else list(back)
        assert got == value and type(got) is type(value), (value, got)


def test_sar_tree_run_puts_its_outputs_in_the_report_folder(tmp_path: Path) -> None:
    config = RunConfig(tree=str(TREE), params=str(PARAMS), keep_alive=True,
                       sim_params=["blocked_areas:=['zone_b:0.8']"],
                       runner_params=["completion:=once"], plugin_paths=PLUGINS)
    inputs = check_config(config)
    settings = mission_settings(config, tmp_path, inputs.places, inputs.apps)
    report = next(p for p in mission_processes(settings, inputs.apps) if p.label == "report")
    assert (settings.trace_file, settings.status_file, report.parameters["report_file"]) == (
        str(tmp_path / "trace.jsonl"), str(tmp_path / "status.json"),
        str(tmp_path / "reports.jsonl"))
    assert settings.exit_on_completion is False  # --keep-alive
    assert "detect" not in settings.extra and settings.nav2_timeout_wall_s is None
    assert settings.extra["sim"] == {"blocked_areas": ["3.5:3:0.8"]}  # the zone's position
    specs = child_specs(config, tmp_path, inputs.places, apps=inputs.apps)
    assert [(s.label, s.executable) for s in specs] == [
        (p.label, p.executable) for p in mission_processes(settings, [SAR])]
    runner = specs[-1]
    assert runner.module == "sar_framework.runner.node"
    assert runner.ros_args == ("--params-file", str(PARAMS), "-p", f"tree:={TREE}",
                               "-p", "use_sim_time:=true", "-p", "exit_on_completion:=false",
                               "-p", f"status_file:={tmp_path / 'status.json'}",
                               "-p", f"plugin_path:={PLUGINS[0]}:{PLUGINS[1]}",
                               "-p", "completion:=once")
