"""``ros2 launch sar_framework search_and_rescue.launch.py nav2:=embedded`` for real.

The real-stack tier: upstream launch / launch_ros / ros2cli built by ``make setup``. Runs the
reference mission to its end twice (the first recorded with ``record:=``), a failing start,
and Ctrl-C in the middle of a mission (every node name unique in ``ros2 node list``; every
process exits 0 without a traceback).
"""

from __future__ import annotations

import re
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest
from e2e.helpers import FAST
from sar_testing import launch_ctrl_c
from sar_testing.launch_ctrl_c import ROS2, ctrl_c_mid_mission, kill_group
from sar_testing.temp_dirs import launch_env

pytestmark = [
    pytest.mark.ros, pytest.mark.slow,
    pytest.mark.skipif(not ROS2.exists(), reason="real-stack tier: ros2cli / launch not built "
                       "(make setup with ../shared/ros-overlay or SAR_ROS_OVERLAY_SRC)"),
]
SPEC_LINES = ("--- Zone 1/4: zone_a", "Reached zone_a.", "Broadcast static TF map -> survivor_1",
              "Report received: survivor_1", "No survivor found at zone_b.",
              "All zones visited. Returning to base.", "Reached base station.",
              "Mission complete.")


def launch(tmp_path: Path, *arguments: str) -> subprocess.Popen[str]:
    print("tier: real ROS 2 stack (ros2 launch from .venv)")
    proc = launch_ctrl_c.launch(tmp_path, *arguments)
    STARTED.append(proc)
    return proc


STARTED: list[subprocess.Popen[str]] = []


@pytest.fixture(autouse=True)
def no_launch_outlives_its_test() -> Iterator[None]:
    """Kill what a failed test left running: later tests must not meet its nodes."""
    yield
    while STARTED:
        kill_group(STARTED.pop())


def test_a_runner_that_fails_fails_the_launch(tmp_path):
    proc = launch(tmp_path, "tree:=no_such_tree")
    output, _ = proc.communicate(timeout=120)
    assert proc.returncode == 1, output
    assert "sar-mission-runner exited with code 2" in output


def test_node_names_are_unique_and_ctrl_c_ends_every_process_cleanly(tmp_path):
    """Every node name listed once; after Ctrl-C launch exits 0, each process finished cleanly.

    The scenario and its checks are shared with ``benchmarks/soak_launch_ctrl_c.py``.
    """
    run = ctrl_c_mid_mission(tmp_path)
    assert run.failures() == [], run.output


REPO = Path(__file__).resolve().parents[2]


def installed_scripts_run_this_checkout() -> bool:
    """Whether the installed ``sar-mission-runner`` (what launch starts) runs this code."""
    import importlib.util

    script = Path(sys.prefix) / "lib" / "sar_framework" / "sar-mission-runner"
    found = re.search(r"^from (\S+) import main", script.read_text(), re.M) \
        if script.exists() else None
    try:
        spec = importlib.util.find_spec(found.group(1)) if found else None
    except ModuleNotFoundError:
        return False
    return spec is not None and spec.origin is not None and \
        Path(spec.origin).resolve().is_relative_to(REPO)


@pytest.mark.skipif(not installed_scripts_run_this_checkout(),
                    reason="the installed sar_framework scripts run another checkout")
def test_two_launches_in_a_row_share_no_survivors_and_no_colour_codes(tmp_path):
    """The reference mission to its end under ros2 launch, recorded, then again.

    Regression: the second launch said '2 survivors already on record ... Repeated report'
    (every launch shared ~/.ros/sar_reports.jsonl), and redirected output carried
    ESC[0m ... ESC[0m\\r on most lines. This checkout's launch file, by path, with no
    report_file: the default. The first launch runs the reference tree with ``record:=``; the
    second runs the reference mission through Nav2's navigator shape
    (trees/examples/search_and_rescue_nav2.yaml, ``tree:=`` a path). Both at ``speed:=40``
    (the e2e tests' FAST: neither is about the speed; the launch argument's default is
    checked in tests/mission/test_launch.py): the same spec lines and survivors."""
    from mcap.reader import make_reader

    record = tmp_path / "mission.mcap"
    env = launch_env(tmp_path, ROS_LOG_DIR=str(tmp_path / "ros-log"), PYTHONUNBUFFERED="1",
                     ROS_HOME=str(tmp_path / "ros_home"))
    env.pop("RCUTILS_COLORIZED_OUTPUT", None)
    outputs = []
    nav2_shape = REPO / "trees" / "examples" / "search_and_rescue_nav2.yaml"
    for arguments in ([f"record:={record}"], [f"tree:={nav2_shape}"]):
        proc = subprocess.Popen(
            [str(ROS2), "launch", str(REPO / "launch" / "search_and_rescue.launch.py"),
             "nav2:=embedded", f"speed:={FAST}", *arguments], stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT, text=True, env=env, start_new_session=True)
        STARTED.append(proc)
        output, _ = proc.communicate(timeout=240)
        assert proc.returncode == 0, output
        outputs.append(output)
    assert "search_and_rescue_nav2.yaml at 2 Hz" in outputs[1]
    for output in outputs:
        assert "(0 survivors already on record)" in output, output
        for line in SPEC_LINES:
            assert line in output, line
        assert "Repeated report" not in output and "Traceback" not in output
        assert "\x1b[" not in output and "\r" not in output
    assert "(py_trees_ros tree" in outputs[0]
    assert len(re.findall(r"process has finished cleanly", outputs[0])) == 5  # + recorder
    with record.open("rb") as stream:  # closed with its summary when the launch shut down
        summary = make_reader(stream).get_summary()
    assert summary is not None
    counts = {summary.channels[c].topic: n
              for c, n in summary.statistics.channel_message_counts.items()}
    for topic in ("/tf_static", "/sar_tree/status"):
        assert counts.get(topic, 0) > 0, (topic, counts)
    runs = sorted((tmp_path / "ros_home" / "sar_runs").iterdir())
    assert len(runs) == 2
    for run in runs:
        ids = [line.split('"survivor_id": "')[1].split('"')[0]
               for line in (run / "reports.jsonl").read_text().splitlines()]
        assert ids == ["survivor_1", "survivor_2"], run
        assert (run / "status.json").exists() and (run / "events.jsonl").exists()


def test_the_fleet_launch_runs_two_robots_to_the_end(tmp_path):
    import json

    env = launch_env(tmp_path, ROS_LOG_DIR=str(tmp_path / "ros-log"),
                     RCUTILS_COLORIZED_OUTPUT="0", PYTHONUNBUFFERED="1")
    # At the e2e tests' FAST speed, as the launches above: the test is not about the speed.
    proc = subprocess.Popen(
        [str(ROS2), "launch", "sar_framework", "fleet.launch.py", "robots:=2",
         f"speed:={FAST}", f"report_dir:={tmp_path}"], stdin=subprocess.DEVNULL,
        stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env,
        start_new_session=True)
    STARTED.append(proc)
    output, _ = proc.communicate(timeout=180)  # outer safety bound (~25 s idle)
    assert proc.returncode == 0, output
    assert "Traceback" not in output
    # simulator, base, coordinator, two detect servers, two runners: all ended on their own
    assert len(re.findall(r"process has finished cleanly", output)) == 7, output
    events = [json.loads(line) for line in
              (tmp_path / "fleet_events.jsonl").read_text(encoding="utf-8").splitlines()]
    searched = sorted(e["zone_id"] for e in events if e["kind"] == "searched")
    assert searched == ["zone_a", "zone_b", "zone_c", "zone_d"], output
    assert events[-1]["kind"] == "complete"
    # the report sar-tree run writes: each robot's, and the run's page
    fleet = json.loads((tmp_path / "fleet.json").read_text(encoding="utf-8"))
    assert fleet["outcome"] == "SUCCESS", fleet
    assert sorted(fleet["robots"]) == ["robot1", "robot2"] and fleet["coordinator"] is True
    assert all((tmp_path / name / "mission.json").is_file() for name in fleet["robots"])
    assert (tmp_path / "fleet.png").stat().st_size > 0
