"""Every input of ``sar-tree run`` is checked before anything starts, all problems at once."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from sar_framework.orchestrate.config import child_specs
from sar_framework.orchestrate.inputs import check_inputs
from sar_framework.orchestrate.options import RunConfig

from .helpers import DEFAULT_TREE, REPO, SIX_ZONES

THREE_MISTAKES = """\
/**:
  ros__parameters:
    zone_order: ["zone_a", "zone_b"]
    zones:
      zone_a: {x: -3.0, y: abc, yaw: 0.0}
      zone_b: {x: 3.5, y: 3.0, yaw: 1.57}
    base_station: {x: 0.0, y: 0.0, yaw: 0.0}
    tick_rate_hz: -2.0
    tick_rate: 2.0
"""


def _problems(tmp_path: Path, **options: object) -> list[str]:
    config = RunConfig(tree=str(DEFAULT_TREE), report_dir=str(tmp_path / "r"), **options)
    inputs, problems = check_inputs(config)
    assert inputs is None or not problems
    return problems


def test_a_params_file_with_three_mistakes_gets_three_located_errors(tmp_path: Path) -> None:
    """Regression: only the first was reported, without a column, after the start."""
    params = tmp_path / "params.yaml"
    params.write_text(THREE_MISTAKES)
    assert _problems(tmp_path, params=str(params)) == [
        f"{params}:5:25: zones.zone_a.y: must be a number, got 'abc'",
        f"{params}:8:5: tick_rate_hz: must be > 0, got -2.0",
        f"{params}:9:5: tick_rate: unknown parameter (did you mean 'tick_rate_hz'?)",
    ]


def test_misspelt_or_mistyped_child_parameters_are_errors(tmp_path: Path) -> None:
    """Regression: `--sim-param blocked_area:=[...]` ran a clean mission with exit 0."""
    problems = _problems(
        tmp_path, sim_params=["blocked_area:=['zone_b']", "speed_scale:=fast"],
        app_params={"detect": ["answer_delay:=1.0"], "report": ["refuse_all:=maybe"]},
        runner_params=["completion:=onse", "tick_rate_hz:=0"])
    assert problems == [
        "--sim-param: blocked_area: unknown parameter (did you mean 'blocked_areas'?)",
        "--sim-param: speed_scale: must be a number, got 'fast'",
        "--detect-param: answer_delay: unknown parameter (did you mean 'answer_delay_wall_s'?)",
        "--report-param: refuse_all: must be true or false, got 'maybe'",
        "--runner-param: completion: must be one of auto, end, once, rest, forever, got 'onse' "
        "(did you mean 'once'?)",
        "--runner-param: tick_rate_hz: must be > 0, got 0",
    ]


def test_blocked_areas_accept_mission_zone_names(tmp_path: Path) -> None:
    """Regression: only the world's marker names were accepted, not the mission's zones."""
    config = RunConfig(tree=str(DEFAULT_TREE), params=str(SIX_ZONES),
                       sim_params=["blocked_areas:=['ne_corner:0.5', 'sw_corner', '1:2:0.3']"])
    inputs, problems = check_inputs(config)
    assert problems == [] and inputs is not None
    sim = next(c for c in child_specs(config, tmp_path, inputs.places) if c.label == "sim")
    assert "blocked_areas:=['5:4.2:0.5', '-5:-4.2:0.6', '1:2:0.3']" in sim.ros_args
    bad = _problems(tmp_path, params=str(SIX_ZONES), sim_params=["blocked_areas:=['ne_cornr']"])
    assert len(bad) == 1 and bad[0].startswith("--sim-param blocked_areas: 'ne_cornr'")
    assert "ne_corner" in bad[0]


def test_phantom_obstacles_are_checked_and_accept_mission_zone_names(tmp_path: Path) -> None:
    config = RunConfig(tree=str(DEFAULT_TREE), params=str(SIX_ZONES),
                       sim_params=["phantom_obstacles:=['ne_corner:0.5', '1:-0.5:0.3']",
                                   "stuck_recoveries:=2"])
    inputs, problems = check_inputs(config)
    assert problems == [] and inputs is not None
    assert inputs.blocked_areas == ()  # a phantom is no wall
    sim = next(c for c in child_specs(config, tmp_path, inputs.places) if c.label == "sim")
    assert "phantom_obstacles:=['5:4.2:0.5', '1:-0.5:0.3']" in sim.ros_args
    bad = _problems(tmp_path, sim_params=["phantom_obstacles:=['1:2']", "stuck_recoveries:=-1"])
    assert bad == ["--sim-param: stuck_recoveries: must be >= 0, got -1",
                   "--sim-param phantom_obstacles: '1:2': expected 'x:y:radius' or a place's "
                   "name (known: zone_a, zone_b, zone_c, zone_d)"]


def test_nothing_starts_and_no_internal_text_leaks(tmp_path: Path) -> None:
    params = tmp_path / "params.yaml"
    params.write_text(THREE_MISTAKES)
    tree = tmp_path / "bad.yaml"
    tree.write_text("format: 1\nroot:\n  sequence:\n    children:\n      - NavigateToZonee: {}\n")
    result = subprocess.run(
        [sys.executable, "-m", "sar_framework", "run", str(tree), "--params", str(params),
         "--sim-param", "blocked_area:=[]", "--report-dir", str(tmp_path / "r")],
        capture_output=True, text=True, timeout=60, cwd=REPO, check=False)
    assert result.returncode == 2, result.stderr
    assert result.stdout == ""
    assert not (tmp_path / "r").exists()
    lines = result.stderr.splitlines()
    assert lines[-1] == "sar-tree run: error: 6 problems in the inputs; nothing was started"
    assert f"{tree}:5:9: error:" in result.stderr
    assert "ValueError" not in result.stderr and "Traceback" not in result.stderr


def test_run_help_explains_completion_and_points_at_the_faults() -> None:
    from sar_framework.cli import main

    result = subprocess.run([sys.executable, "-m", "sar_framework", "run", "--help"],
                            capture_output=True, text=True, timeout=60, check=False)
    text = " ".join(result.stdout.split())
    assert main(["faults"]) == 0
    for words in ("end (default) = the mission ends when the tree reaches its declared end",
                  "auto = the tree file's key, else end",
                  "see `sar-tree faults`",
                  "--timeout S give up after S wall seconds",
                  "--sim-timeout S give up once the tree has ticked S seconds on its ROS clock"):
        assert words in text


def test_every_listed_fault_is_a_parameter_the_child_reads(capsys) -> None:
    from sar_framework.cli import main
    from sar_framework.orchestrate.faults import FAULTS
    from sar_framework.orchestrate.inputs import child_parameters

    assert main(["faults"]) == 0
    listed = capsys.readouterr().out
    for fault in FAULTS:
        assert f"{fault.option} {fault.example}".strip() in listed
        if fault.name:
            param = next(p for p in child_parameters(fault.child) if p.name == fault.name)
            assert param.description.removeprefix("fault: ") in listed
