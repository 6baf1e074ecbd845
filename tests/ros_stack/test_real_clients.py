"""The reference mission on the real ROS 2 Jazzy stack, checked with the real tools.

One ``sar-tree run trees/search_and_rescue.yaml --keep-alive`` runs for the module on the
run's leased domain. Once it is complete, upstream's own clients are run against it as
subprocesses (each bounded by a timeout) and their output is compared with what the mission
files say: tf2_ros's Buffer + TransformListener (what ``tf2_echo`` does), ``ros2 topic echo``,
``ros2 service call``, ``ros2 action list``, ``ros2 node list``, ``ros2 interface show`` and
py_trees_ros's ``py-trees-tree-watcher``.

The module is skipped, with one line saying why, when the real stack is not built (the
fallback tier: ``make setup`` without the ROS 2 sources).
"""

from __future__ import annotations

import importlib.util
import os
import re
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest
import yaml
from e2e.helpers import DEFAULT_TREE, FAST, sar_tree_run
from sar_testing.processes import NodeProcess

REPO = Path(__file__).resolve().parents[2]
BIN = Path(sys.executable).parent
TF2_LOOKUP = Path(__file__).with_name("tf2_lookup.py")
REAL_MODULES = ("tf2_ros", "py_trees_ros", "nav2_simple_commander", "ros2cli")
REAL_TOOLS = ("ros2", "py-trees-tree-watcher")
#: Bound for one command-line tool (ros2 starts in ~1-2 s; discovery adds a little).
TOOL_TIMEOUT_S = 30.0


def missing_real_parts() -> list[str]:
    """The real-stack modules and tools this interpreter's environment lacks."""
    missing = [m for m in REAL_MODULES if importlib.util.find_spec(m) is None]
    return missing + [t for t in REAL_TOOLS if not (BIN / t).exists()]


MISSING = missing_real_parts()
pytestmark = [
    pytest.mark.ros, pytest.mark.slow,
    pytest.mark.skipif(bool(MISSING), reason="fallback tier: the real ROS 2 stack is not built "
                       f"(missing {', '.join(MISSING)}); make setup with ../shared/ros-overlay"),
]


@dataclass
class Mission:
    """The running mission and what its files say it should show."""

    process: object
    report: Path
    survivors: list[tuple[str, str, float, float]]  # (frame, zone, x, y) in discovery order
    zones: list[str]


def expected_survivors() -> tuple[list[tuple[str, str, float, float]], list[str]]:
    """survivor_N frames from config/survivors.yaml, numbered in the mission's zone order."""
    params = yaml.safe_load((REPO / "config" / "mission_params.yaml").read_text())
    zones = next(iter(params.values()))["ros__parameters"]["zone_order"]
    table = yaml.safe_load((REPO / "config" / "survivors.yaml").read_text())["survivors"]
    found = [zone for zone in zones if zone in table]
    return ([(f"survivor_{i}", zone, float(table[zone]["x"]), float(table[zone]["y"]))
             for i, zone in enumerate(found, start=1)], zones)


def tool(*args: str, timeout: float = TOOL_TIMEOUT_S, env: dict[str, str] | None = None) -> str:
    """Run an executable of the venv's bin (a ROS tool); return stdout, assert exit 0."""
    command = [str(BIN / args[0]), *args[1:]]
    done = subprocess.run(command, capture_output=True, text=True, timeout=timeout,
                          env={**os.environ, **(env or {})}, check=False)
    assert done.returncode == 0, f"{' '.join(args)} exited {done.returncode}:\n" \
                                 f"{done.stdout}\n{done.stderr}"
    return done.stdout


def tool_until(check: str | tuple[str, ...], *args: str, attempts: int = 4) -> str:
    """Run a tool until its output holds ``check`` (all of them: DDS discovery takes a
    moment, and another process may be discovered a run later than the first)."""
    checks = (check,) if isinstance(check, str) else check
    out = ""
    for _ in range(attempts):
        out = tool(*args)
        if all(c in out for c in checks):
            break
        time.sleep(1.0)
    return out


@pytest.fixture(scope="module")
def mission(tmp_path_factory: pytest.TempPathFactory,
            request: pytest.FixtureRequest) -> Iterator[Mission]:
    """The reference mission, complete and kept alive until the module's tests are done."""
    reporter = request.config.pluginmanager.get_plugin("terminalreporter")
    if reporter is not None:
        reporter.write_line("tests/ros_stack: real-stack tier (tf2_ros, py_trees_ros, "
                            "nav2_simple_commander, ros2cli built from the overlay)")
    report = tmp_path_factory.mktemp("real_clients") / "report"
    process = sar_tree_run([str(DEFAULT_TREE), "--keep-alive", "--speed", FAST], report)
    survivors, zones = expected_survivors()
    try:
        process.wait_for_output(r"Staying up \(--keep-alive\)", timeout=120)
        assert "Mission complete." in process.output, process.output
        yield Mission(process, report, survivors, zones)
    finally:
        process.send_signal(signal.SIGINT)
        try:
            process.wait(timeout=15)
        finally:
            process.stop()
            # `ros2 action list` has no --no-daemon: stop the daemon it spawned on our domain.
            subprocess.run([str(BIN / "ros2"), "daemon", "stop"], capture_output=True,
                           timeout=TOOL_TIMEOUT_S, env=os.environ.copy(), check=False)


def test_the_runner_used_py_trees_ros_and_basic_navigator(mission: Mission) -> None:
    runner_log = (mission.report / "runner.log").read_text(errors="replace")
    assert re.search(r"Ticking \S+ at [\d.]+ Hz \(py_trees_ros tree, \d+ nodes\)",
                     runner_log), runner_log
    assert "with BasicNavigator" in runner_log, runner_log


def test_the_real_classes_are_chosen_when_importable() -> None:
    import py_trees
    from nav2_simple_commander.robot_navigator import BasicNavigator
    from py_trees_ros.trees import BehaviourTree
    from sar_testing.spin import ros_node
    from tf2_ros import StaticTransformBroadcaster

    from sar_framework.ros.static_tf import make_static_broadcaster
    from sar_framework.runner.nav2_startup import basic_navigator_class
    from sar_framework.runner.tree_ticker import create_behaviour_tree, implementation_name

    tree = create_behaviour_tree(py_trees.behaviours.Success("only"))
    assert type(tree) is BehaviourTree and implementation_name(tree) == "py_trees_ros"
    assert basic_navigator_class() is BasicNavigator
    with ros_node("real_classes_probe") as (node, _executor):
        assert type(make_static_broadcaster(node)) is StaticTransformBroadcaster


def test_tf2_listener_looks_up_every_survivor(mission: Mission) -> None:
    frames = [frame for frame, *_ in mission.survivors]
    assert frames, "config/survivors.yaml places no survivor in the mission's zones"
    done = subprocess.run([sys.executable, str(TF2_LOOKUP), "map", *frames, "--timeout", "15"],
                          capture_output=True, text=True, timeout=TOOL_TIMEOUT_S, check=False)
    assert done.returncode == 0, done.stdout + done.stderr
    for frame, _zone, x, y in mission.survivors:
        assert f"map -> {frame}: {x:.3f} {y:.3f} 0.000" in done.stdout, done.stdout


def test_topic_echo_tf_static_once_holds_every_survivor(mission: Mission) -> None:
    out = tool("ros2", "topic", "echo", "/tf_static", "tf2_msgs/msg/TFMessage", "--once",
               "--no-daemon", "--qos-durability", "transient_local",
               "--qos-reliability", "reliable", "--timeout", "15")
    message = next(yaml.safe_load_all(out))
    by_frame = {t["child_frame_id"]: t for t in message["transforms"]}
    assert set(by_frame) == {frame for frame, *_ in mission.survivors}, out
    for frame, _zone, x, y in mission.survivors:
        transform = by_frame[frame]
        assert transform["header"]["frame_id"] == "map"
        translation = transform["transform"]["translation"]
        assert (translation["x"], translation["y"]) == pytest.approx((x, y)), out


def test_service_call_detect_answers_as_the_survivors_table(mission: Mission) -> None:
    survivors = {zone: (x, y) for _frame, zone, x, y in mission.survivors}
    # A zone with a survivor and one without (each call is a ros2 CLI process of its own).
    found = next(zone for zone in mission.zones if zone in survivors)
    empty = next(zone for zone in mission.zones if zone not in survivors)
    for zone in (found, empty):
        out = tool("ros2", "service", "call", "/detect_survivor",
                   "sar_interfaces/srv/DetectSurvivor", f"{{zone_id: {zone}}}")
        match = re.search(r"DetectSurvivor_Response\(found=(True|False), "
                          r"survivor_x=(\S+), survivor_y=(\S+)\)", out)
        assert match, out
        assert (match[1] == "True") == (zone in survivors), out
        if zone in survivors:
            assert (float(match[2]), float(match[3].rstrip(")"))) == \
                pytest.approx(survivors[zone]), out


def test_action_list_shows_navigate_to_pose_with_its_type(mission: Mission) -> None:
    out = tool_until("/navigate_to_pose", "ros2", "action", "list", "-t")
    assert "/navigate_to_pose [nav2_msgs/action/NavigateToPose]" in out.splitlines(), out


def test_node_list_names_are_unique(mission: Mission) -> None:
    out = tool_until(("/sar_mission_runner", "/bt_navigator", "/amcl"), "ros2", "node", "list",
                     "--no-daemon", "--spin-time", "3", attempts=8)
    names = out.split()
    assert len(names) == len(set(names)), f"duplicate node names: {names}"
    assert {"/sar_mission_runner", "/bt_navigator", "/amcl"} <= set(names), names


@pytest.mark.parametrize("service", ["DetectSurvivor", "ReportSurvivor"])
def test_interface_show_matches_our_srv_files(service: str) -> None:
    ours = (REPO / "interfaces" / "sar_interfaces" / "srv" / f"{service}.srv").read_text()
    shown = tool("ros2", "interface", "show", f"sar_interfaces/srv/{service}").splitlines()
    # Our lines in order; nested types (geometry_msgs/PointStamped) are expanded, tab-indented.
    top_level = [line.rstrip() for line in shown if not line.startswith("\t")]
    assert top_level == [line.rstrip() for line in ours.strip().splitlines()], "\n".join(shown)


def tree_node_names() -> list[str]:
    from sar_framework import load_spec

    return [node.name for node in load_spec(DEFAULT_TREE).nodes()]


def test_tree_watcher_dot_graph_shows_our_tree(mission: Mission, tmp_path: Path) -> None:
    # Without xdot the watcher prints the dot source (and writes its files to $TMPDIR).
    # the watcher's node gets 5 s to discover our service ("service not found" after): a
    # loaded machine can need longer, so it may be run again (outer safety bound: 4 runs)
    for _ in range(4):
        done = subprocess.run([str(BIN / "py-trees-tree-watcher"), "--dot-graph"],
                              capture_output=True, text=True, timeout=TOOL_TIMEOUT_S,
                              env={**os.environ, "TMPDIR": str(tmp_path)}, check=False)
        if "service not found" not in done.stdout + done.stderr:
            break
    assert done.returncode == 0, done.stdout + done.stderr
    out = done.stdout
    assert "digraph" in out, out
    dot_nodes = {m[2] for m in re.finditer(r'^("?)(.+?)\1 \[label=', out, re.MULTILINE)}
    assert dot_nodes == set(tree_node_names()), out


def test_tree_watcher_streams_snapshots_of_our_tree(mission: Mission, tmp_path: Path) -> None:
    names = tree_node_names()

    def seen_all(out: str) -> bool:
        return bool(re.search(r"Tick \d+", out)) and ("Statistics" in out or "Duration" in out) \
            and all(name in out for name in names)

    # Streaming mode runs until Ctrl-C: stopped once every node was in a snapshot (the
    # watcher renders every tick, a core's worth of work), or at the outer safety bound.
    # The watcher gives its new node 5 s to discover our snapshot service, then gives up
    # ("service not found"); on a loaded machine discovery can take longer: start it again.
    deadline = time.monotonic() + 120.0  # outer safety bound (a few seconds expected)
    out = ""
    while time.monotonic() < deadline:  # outer safety bound
        with NodeProcess([str(BIN / "py-trees-tree-watcher"), "--snapshots", "-s"],
                         "watcher", log_dir=tmp_path) as watcher:
            while not seen_all(watcher.output) and watcher.poll() is None \
                    and time.monotonic() < deadline:  # outer safety bound
                time.sleep(0.1)
        out = watcher.output
        if "service not found" not in out:
            break
    assert re.search(r"Tick \d+", out), out
    assert "Statistics" in out or "Duration" in out, out
    missing = [name for name in names if name not in out]
    assert not missing, f"nodes missing from the watcher's snapshots: {missing}\n{out}"
