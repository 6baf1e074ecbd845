"""The tree runner as a child process: rate, exit codes, status file, SIGINT, bad input."""

from __future__ import annotations

import json
import signal
import time
from collections.abc import Callable
from pathlib import Path

import py_trees
import pytest
from sar_plugins.sar.events import SarKind
from sar_testing.processes import NodeProcess

from sar_framework.engine.spec import Category, NodeSpec, TreeSpec
from sar_framework.events.event import REASON_KINDS, EventKind, MissionEvent
from sar_framework.events.jsonl import EVENTS_FILE, read_events
from sar_framework.runner.status_file import StatusFileWriter

ros = pytest.mark.ros
REPO = Path(__file__).resolve().parents[2]
PLUGINS = Path(__file__).resolve().parent / "runner_plugins"
NODES = REPO / "tests" / "sar_testing" / "nodes"
MISSION_PARAMS = REPO / "config" / "mission_params.yaml"
RUNNER = ["-m", "sar_framework.runner.node"]

OK_TREE = """\
format: 1
name: runner_ok
root:
  sequence:
    name: Steps
    memory: true
    children:
      - selector:
          name: Choose
          memory: false
          children:
            - Countdown: {name: "Check?", ticks: 0, succeed: false, message: "not this way"}
            - Countdown: {name: Work, ticks: 20}
      - Countdown: {name: Last, ticks: 0}
"""

FAIL_TREE = """\
format: 1
name: runner_fail
root:
  sequence:
    name: Steps
    memory: true
    children:
      - Countdown: {name: Prepare, ticks: 1}
      - Countdown: {name: Broken, ticks: 2, succeed: false, message: "boom: no luck"}
"""


def runner_args(tree: Path, status: Path | None = None, *extra: str,
                params: Path = MISSION_PARAMS) -> list[str]:
    args = [*RUNNER, "--ros-args", "--params-file", str(params), "-p", f"tree:={tree}",
            "-p", f"plugin_path:={PLUGINS}", "-p", "seed_amcl:=false"]
    if status is not None:
        args += ["-p", f"status_file:={status}"]
    for item in extra:
        args += ["-p", item]
    return args


def write_tree(tmp_path: Path, text: str, name: str = "tree.yaml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def verdicts(status: Path) -> list[MissionEvent]:
    """The leaf verdicts (``status`` events SUCCESS/FAILURE) in the events beside ``status``."""
    return [e for e in read_events(status.with_name(EVENTS_FILE))
            if e.kind == EventKind.STATUS and e.status in ("SUCCESS", "FAILURE")]


def reasons(status: Path) -> list[MissionEvent]:
    """The reason events (failure, timeout, cancel, retry, skip) beside ``status``."""
    return [e for e in read_events(status.with_name(EVENTS_FILE)) if e.kind in REASON_KINDS]


def run_to_end(args: list[str], tmp_path: Path, label: str = "runner",
               timeout: float = 30.0) -> tuple[int, str]:
    process = NodeProcess(args, label, log_dir=tmp_path).start()
    try:
        code = process.wait(timeout=timeout)
    finally:
        process.stop()
    return code, process.output


def wait_for_status(status: Path, found: Callable[[dict], bool], runner: NodeProcess) -> dict:
    """Poll the runner's status file until ``found`` says yes; the document then."""
    deadline = time.monotonic() + 120  # outer safety bound (a few seconds expected)
    doc: dict = {}
    while not doc or not found(doc):
        assert runner.returncode() is None, runner.output
        assert time.monotonic() < deadline, f"status never matched: {doc}"  # outer safety bound
        time.sleep(0.05)
        try:
            doc = json.loads(status.read_text())
        except (OSError, ValueError):
            doc = {}
    return doc


@ros
def test_success_ticks_at_the_rate_and_writes_the_status_file(tmp_path):
    status = tmp_path / "out" / "status.json"
    tree = write_tree(tmp_path, OK_TREE)
    code, output = run_to_end(runner_args(tree, status, "exit_on_completion:=true",
                                          "completion:=once", "tick_rate_hz:=20.0",
                                          "print_tree:=true"), tmp_path)
    assert code == 0, output
    assert "Mission complete." in output
    assert "Ticking" in output and "at 20 Hz" in output
    assert "--> Work [✓] -- done after 20 ticks (4 zones)" in output  # print_tree
    assert "Traceback" not in output

    doc = json.loads(status.read_text())
    assert doc["tree"] == str(tree)
    assert (doc["status"], doc["complete"]) == ("SUCCESS", True)
    assert doc["ticks"] == 21  # 20 RUNNING ticks, then the verdict
    assert doc["nodes"] == {"0": "SUCCESS", "0.0": "SUCCESS", "0.0.0": "FAILURE",
                            "0.0.1": "SUCCESS", "0.1": "SUCCESS"}
    events = verdicts(status)
    assert [(e.node_uid, e.node_name, e.node_kind, e.status, e.message) for e in events] == [
        # the reactive selector re-checks "Check?" every tick: recorded once
        ("0.0.0", "Check?", "Countdown", "FAILURE", "not this way"),
        ("0.0.1", "Work", "Countdown", "SUCCESS", "done after 20 ticks (4 zones)"),
        ("0.1", "Last", "Countdown", "SUCCESS", "done after 0 ticks (4 zones)"),
    ]
    assert reasons(status) == []  # a condition saying "no" is a decision, not a failure
    # 20 periods of 50 ms between the first tick and Work's verdict, on the ROS clock
    took = events[1].sim_s - doc["sim_start_s"]
    assert took >= 0.95, took  # later under load, never sooner
    assert doc["sim_end_s"] >= events[-1].sim_s
    assert 0 < doc["wall_first_tick_s"] <= events[1].wall_s <= doc["wall_duration_s"]
    (completion,) = [e for e in read_events(status.with_name(EVENTS_FILE))
                     if e.kind == EventKind.COMPLETION]
    assert (completion.status, completion.node_uid) == ("SUCCESS", "0")


@ros
def test_failure_exits_1_and_lists_the_failure(tmp_path):
    status = tmp_path / "status.json"
    tree = write_tree(tmp_path, FAIL_TREE)
    code, output = run_to_end(runner_args(tree, status, "exit_on_completion:=true",
                                          "completion:=once", "tick_rate_hz:=20.0"),
                              tmp_path)
    assert code == 1, output
    assert "Mission failed (Broken: boom: no luck)." in output
    doc = json.loads(status.read_text())
    assert doc["status"] == "FAILURE"
    assert [(e.kind, e.node_uid, e.node_name, e.message) for e in reasons(status)] == [
        (EventKind.FAILURE, "0.1", "Broken", "boom: no luck")]
    assert [(e.kind, e.status) for e in read_events(status.with_name(EVENTS_FILE))][-1] == (
        EventKind.COMPLETION, "FAILURE")
    assert "Broken [0.1]: boom: no luck" in output  # the reason line
    assert doc["nodes"]["0"] == "FAILURE"


@ros
def test_sigint_mid_run_cancels_the_nav2_goal_and_exits_0(tmp_path):
    tree = write_tree(tmp_path, """\
format: 1
name: one_zone
root:
  sequence:
    name: Go
    memory: true
    children:
      - NavigateToZone: {}
""")
    status = tmp_path / "status.json"
    with NodeProcess([str(NODES / "slow_navigate_server.py")], "nav", log_dir=tmp_path) as nav:
        nav.wait_for_output("ready")
        runner = NodeProcess(runner_args(tree, status, "tick_rate_hz:=10.0"), "runner",
                             log_dir=tmp_path).start()
        try:
            runner.wait_for_output(r"--- Zone 1/4: zone_a \(-3\.00, 3\.00\) ---", timeout=30)
            nav.wait_for_output("goal executing", timeout=30)  # the goal is in flight
            runner.send_signal(signal.SIGINT)
            code = runner.wait(timeout=30)  # outer safety bound (under 1 s expected)
        finally:
            runner.stop()
        nav.wait_for_output("goal canceled", timeout=30)
    assert code == 0, runner.output  # a requested shutdown is clean (was 130)
    assert "SIGINT: stopping the tree" in runner.output
    assert "stopped running leaves: NavigateToZone" in runner.output
    assert "Traceback" not in runner.output
    doc = json.loads(status.read_text())
    assert doc["status"] == "RUNNING"
    assert doc["nodes"]["0.0"] == "RUNNING"


@ros
def test_sigint_after_completion_exits_with_the_verdict(tmp_path):
    tree = write_tree(tmp_path, """\
format: 1
name: rests_at_success
root:
  one_shot:
    name: Once
    policy: on_completion
    child:
      Countdown: {name: Work, ticks: 1}
""")
    runner = NodeProcess(runner_args(tree, None, "tick_rate_hz:=20.0"), "runner",
                         log_dir=tmp_path).start()
    try:
        runner.wait_for_output("Mission complete.")
        time.sleep(0.3)  # still ticking: the tree idles at SUCCESS
        runner.send_signal(signal.SIGINT)
        code = runner.wait(timeout=10)
    finally:
        runner.stop()
    assert code == 0, runner.output
    assert runner.output.count("Mission complete.") == 1


@ros
def test_a_root_that_succeeds_then_restarts_is_not_complete(tmp_path):
    """The reference tree's root succeeds after every zone; only rest means the end."""
    status = tmp_path / "status.json"
    tree = write_tree(tmp_path, OK_TREE.replace("ticks: 20", "ticks: 2"))
    runner = NodeProcess(runner_args(tree, status, "exit_on_completion:=true",
                                     "completion:=rest", "tick_rate_hz:=20.0"), "runner",
                         log_dir=tmp_path).start()
    try:
        # Dozens of ticks, the root SUCCESS every fourth one (the status file counts them).
        wait_for_status(status, lambda doc: doc["ticks"] >= 40, runner)
        assert runner.returncode() is None, runner.output
        runner.send_signal(signal.SIGINT)
        code = runner.wait(timeout=10)
    finally:
        runner.stop()
    assert code == 0
    assert "Mission complete." not in runner.output
    assert json.loads(status.read_text())["complete"] is False


@ros
def test_a_tree_without_a_one_shot_at_its_end_runs_once_by_default(tmp_path):
    """Regression: such a tree was ticked again after its root succeeded (completion: rest)."""
    status = tmp_path / "status.json"
    tree = write_tree(tmp_path, OK_TREE.replace("ticks: 20", "ticks: 2"))
    runner = NodeProcess(runner_args(tree, status, "tick_rate_hz:=20.0"), "runner",
                         log_dir=tmp_path).start()
    try:
        runner.wait_for_output("Mission complete.")
        ticks = json.loads(status.read_text())["ticks"]
        time.sleep(0.6)  # a dozen tick periods: no tick may come
        runner.send_signal(signal.SIGINT)
        code = runner.wait(timeout=10)
    finally:
        runner.stop()
    assert code == 0, runner.output
    assert "completion: end (default; the mission ends when the tree reaches its declared " \
        "end: the root's first SUCCESS or FAILURE (no one_shot on its final path))" \
        in runner.output
    doc = json.loads(status.read_text())
    assert doc["ticks"] == ticks
    assert doc["complete"] is True
    assert [e.node_name for e in verdicts(status) if e.status == "SUCCESS"].count("Work") == 1


@ros
def test_sigint_twice_terminates_a_running_leaf_and_exits_0(tmp_path):
    tree = write_tree(tmp_path, "format: 1\nname: forever\nroot:\n  Forever: {name: Wait}\n")
    status = tmp_path / "status.json"
    runner = NodeProcess(runner_args(tree, status, "tick_rate_hz:=10.0"), "runner",
                         log_dir=tmp_path).start()
    try:
        wait_for_status(status, lambda doc: doc["running"] == ["0"], runner)  # Wait runs
        runner.send_signal(signal.SIGINT)  # a terminal's Ctrl-C ...
        time.sleep(0.05)
        runner.send_signal(signal.SIGINT)  # ... and ros2 launch forwarding it once more
        code = runner.wait(timeout=10)
    finally:
        runner.stop()
    assert code == 0, runner.output  # was 130 (KeyboardInterrupt on the second signal)
    assert "Traceback" not in runner.output and "KeyboardInterrupt" not in runner.output
    assert "Wait terminated (INVALID)" in runner.output


@ros
def test_bad_tree_exits_2_with_the_diagnostic(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    write_tree(tmp_path, OK_TREE.replace("Countdown: {name: Last", "Countdwn: {name: Last"),
               "bad.yaml")
    status = tmp_path / "status.json"
    code, output = run_to_end(runner_args(Path("bad.yaml"), status), tmp_path)
    assert code == 2, output
    assert "cannot load bad.yaml:" in output
    assert "bad.yaml:14:9: error: unknown plugin 'Countdwn' (did you mean 'Countdown'?)" in output
    assert "Traceback" not in output
    doc = json.loads(status.read_text())
    assert (doc["status"], doc["ticks"], doc["error"]["step"]) == ("INVALID", 0, "tree")


@ros
def test_missing_tree_file_exits_2(tmp_path):
    code, output = run_to_end(runner_args(tmp_path / "nope.yaml"), tmp_path)
    assert code == 2, output
    assert "nope.yaml" in output
    assert "Traceback" not in output


@ros
def test_bad_params_file_is_caught_before_rcl(tmp_path):
    params = tmp_path / "params.yaml"
    params.write_text("/**:\n  ros__parameters:\n    zone_order: [\"zone_a\"\n")
    code, output = run_to_end(runner_args(tmp_path / "t.yaml", params=params), tmp_path)
    assert code == 2, output
    assert f"{params}:4:1: YAML syntax error" in output
    assert "rcl" not in output.replace("[sar_mission_runner]", "")
    assert "Traceback" not in output


@ros
def test_bad_runner_parameter(tmp_path):
    tree = write_tree(tmp_path, OK_TREE)
    code, output = run_to_end(runner_args(tree, None, "exit_on_completion:=1"), tmp_path)
    assert code == 2, output
    assert "parameters: exit_on_completion: must be true or false, got 1" in output


@ros
def test_sim_timeout_stops_the_tree_and_exits_4_naming_what_ran(tmp_path):
    """``sim_timeout_s`` counts the runner's ROS clock from the first tick."""
    status = tmp_path / "status.json"
    tree = write_tree(tmp_path, "format: 1\nname: forever\nroot:\n  Forever: {name: Wait}\n")
    code, output = run_to_end(runner_args(tree, status, "sim_timeout_s:=1.5",
                                          "exit_on_completion:=true", "tick_rate_hz:=10.0"),
                              tmp_path, timeout=60.0)  # outer safety bound
    assert code == 4, output
    assert "sim_timeout_s: the mission is not complete after" in output
    assert "Wait terminated (INVALID)" in output
    doc = json.loads(status.read_text())
    assert doc["complete"] is False and doc["running"] == ["0"]
    assert doc["sim_end_s"] - doc["sim_start_s"] >= 1.5


@ros
def test_setup_timeout_exits_3(tmp_path):
    tree = write_tree(tmp_path, "format: 1\nname: slow\nroot:\n  SlowSetup: {seconds: 10.0}\n")
    code, output = run_to_end(runner_args(tree, None, "setup_timeout_wall_s:=1.0"), tmp_path)
    assert code == 3, output  # 1 s, not the 10 s of SlowSetup's sleep
    assert "tree setup failed" in output and "SlowSetup" in output
    assert "Traceback" not in output


@ros
@pytest.mark.parametrize("namespace", ["", "/robot1"], ids=["root", "fleet_robot"])
def test_no_nav2_is_a_bounded_start_up_failure(tmp_path, namespace):
    # In a namespace (a fleet's robot) the message names the service the runner waited for.
    tree = write_tree(tmp_path, OK_TREE)
    status = tmp_path / "status.json"
    args = [a if a != "seed_amcl:=false" else "seed_amcl:=true"
            for a in runner_args(tree, status, "nav2_timeout_wall_s:=2.0")]
    if namespace:
        args += ["-r", f"__ns:={namespace}"]
    code, output = run_to_end(args, tmp_path)
    assert code == 3, output
    assert (f"amcl never reported ACTIVE ({namespace}/amcl/get_state never appeared) within "
            "2 s: is Nav2 (or the simulator) running?") in output
    doc = json.loads(status.read_text())
    assert doc["error"]["step"] == "nav2"
    assert doc["error"]["message"].startswith("amcl never reported ACTIVE")


@ros
def test_a_bad_tree_is_named_even_when_nav2_never_comes(tmp_path):
    """The tree is built while Nav2 is awaited: without Nav2, its error still comes first."""
    tree = write_tree(tmp_path, "format: 1\nname: bad\nroot:\n  NoSuchLeaf: {}\n")
    status = tmp_path / "status.json"
    args = [a if a != "seed_amcl:=false" else "seed_amcl:=true"
            for a in runner_args(tree, status, "nav2_timeout_wall_s:=1.0")]
    code, output = run_to_end(args, tmp_path)
    assert code == 2, output
    assert f"cannot load {tree}" in output and "unknown plugin 'NoSuchLeaf'" in output
    assert json.loads(status.read_text())["error"]["step"] == "tree"


# --- the status file writer alone (no ROS) -----------------------------------------------

def test_status_writer_suppresses_idle_repeats_but_keeps_new_executions():
    from sar_framework.engine.diagnostics import SourceLocation

    where = SourceLocation("t.yaml", 1, 1)
    leaf_spec = NodeSpec("Check", Category.LEAF, "Check?", "0.0", where)
    root_spec = NodeSpec("selector", Category.COMPOSITE, "Root", "0", where, children=[leaf_spec])
    spec = TreeSpec("t", "", root_spec, "t.yaml")
    verdicts = iter([py_trees.common.Status.FAILURE] * 3 + [py_trees.common.Status.SUCCESS]
                    + [py_trees.common.Status.FAILURE])

    class Check(py_trees.behaviour.Behaviour):
        def update(self):
            return next(verdicts)

    leaf = Check("Check?")
    root = py_trees.composites.Selector("Root", memory=False, children=[leaf])
    # ticked on and on (a complete mission is never ticked again, so: forever)
    writer = StatusFileWriter("t.yaml", spec, {"0": root, "0.0": leaf}, lambda: 0.0,
                              completion="forever")
    tree = py_trees.trees.BehaviourTree(root)
    tree.visitors.append(writer)
    tree.add_post_tick_handler(writer.after_tick)
    for _ in range(5):
        tree.tick()
    assert [e["status"] for e in writer.events] == ["FAILURE", "SUCCESS", "FAILURE"]
    assert writer.ticks == 5
    # the root failed on the ticks its only child failed instantly: one failure per
    # execution (ticks 1-3 are one, idling; tick 5 is a new one), whatever the timing
    assert [f["uid"] for f in writer.failures] == ["0.0", "0.0"]
    assert writer.complete is False


def test_status_writer_rest_detection():
    from sar_framework.engine.diagnostics import SourceLocation

    where = SourceLocation("t.yaml", 1, 1)
    leaf_spec = NodeSpec("Step", Category.LEAF, "Step", "0.0", where)
    root_spec = NodeSpec("one_shot", Category.DECORATOR, "Once", "0", where, children=[leaf_spec])
    spec = TreeSpec("t", "", root_spec, "t.yaml")

    class Step(py_trees.behaviour.Behaviour):
        def __init__(self):
            super().__init__("Step")
            self.calls = 0

        def update(self):
            self.calls += 1
            done = self.calls >= 2
            return py_trees.common.Status.SUCCESS if done else py_trees.common.Status.RUNNING

    leaf = Step()
    root = py_trees.decorators.OneShot("Once", leaf, py_trees.common.OneShotPolicy.ON_COMPLETION)
    writer = StatusFileWriter("t.yaml", spec, {"0": root, "0.0": leaf}, lambda: 0.0)
    tree = py_trees.trees.BehaviourTree(root)
    tree.visitors.append(writer)
    tree.add_post_tick_handler(writer.after_tick)
    states = []
    for _ in range(4):
        tree.tick()
        states.append((writer.status.name, writer.complete))
    assert states == [("RUNNING", False), ("SUCCESS", False), ("SUCCESS", True), ("SUCCESS", True)]
    assert writer.document()["complete"] is True
    with pytest.raises(ValueError, match="completion"):
        StatusFileWriter("t.yaml", spec, {}, lambda: 0.0, completion="sometimes")


def test_status_writer_running_lists_only_what_runs_now():
    """Regression: a leaf halted by its parent must not be reported as still running.

    ``nodes`` keeps each node's last non-INVALID status (for the coloured tree.svg), so a
    halted leaf stays "RUNNING" there; ``running`` is what runs after the last tick, which is
    what a timeout message must name.
    """
    from sar_framework.engine.diagnostics import SourceLocation

    where = SourceLocation("t.yaml", 1, 1)
    guard_spec = NodeSpec("Guard", Category.LEAF, "Guard?", "0.0", where)
    work_spec = NodeSpec("Work", Category.LEAF, "Work", "0.1", where)
    root_spec = NodeSpec("selector", Category.COMPOSITE, "Root", "0", where,
                         children=[guard_spec, work_spec])
    spec = TreeSpec("t", "", root_spec, "t.yaml")
    guard_verdicts = iter([py_trees.common.Status.FAILURE] + [py_trees.common.Status.RUNNING] * 3)

    class Guard(py_trees.behaviour.Behaviour):
        def update(self):
            return next(guard_verdicts)

    class Work(py_trees.behaviour.Behaviour):
        def update(self):
            return py_trees.common.Status.RUNNING

    guard, work = Guard("Guard?"), Work("Work")
    root = py_trees.composites.Selector("Root", memory=False, children=[guard, work])
    writer = StatusFileWriter("t.yaml", spec, {"0": root, "0.0": guard, "0.1": work},
                              lambda: 0.0)
    tree = py_trees.trees.BehaviourTree(root)
    tree.visitors.append(writer)
    tree.add_post_tick_handler(writer.after_tick)
    tree.tick()  # Guard fails, Work runs
    assert writer.document()["running"] == ["0", "0.1"]
    tree.tick()  # Guard now runs: the reactive selector halts Work
    document = writer.document()
    assert document["running"] == ["0", "0.0"]
    assert document["nodes"]["0.1"] == "RUNNING"  # last non-INVALID status, for colouring


@ros
@pytest.mark.slow
def test_reference_mission_through_the_runner_and_both_servers(tmp_path):
    """trees/search_and_rescue.yaml with the real servers and a quick fake Nav2."""
    reports = tmp_path / "reports.jsonl"
    status = tmp_path / "status.json"
    nav = NodeProcess([str(NODES / "quick_navigate_server.py")], "nav", log_dir=tmp_path)
    detect = NodeProcess(["-m", "sar_plugins.sar.servers.detect_survivor_server"], "detect",
                         log_dir=tmp_path)
    report = NodeProcess(["-m", "sar_plugins.sar.servers.report_survivor_server", "--ros-args",
                          "-p", f"report_file:={reports}"], "report", log_dir=tmp_path)
    with nav, detect, report:
        for server in (nav, detect, report):
            server.wait_for_output("ready")
        args = [*RUNNER, "--ros-args", "--params-file", str(MISSION_PARAMS),
                "-p", f"tree:={REPO / 'trees' / 'search_and_rescue.yaml'}",
                "-p", "seed_amcl:=false", "-p", "exit_on_completion:=true",
                "-p", "tick_rate_hz:=10.0", "-p", f"status_file:={status}"]
        code, output = run_to_end(args, tmp_path, timeout=90)
    assert code == 0, output
    expected = [
        "--- Zone 1/4: zone_a (-3.00, 3.00) ---", "Reached zone_a.",
        "--- Zone 2/4: zone_b (3.50, 3.00) ---", "No survivor found at zone_b.",
        "--- Zone 3/4: zone_c (4.00, -3.00) ---", "Reached zone_c.",
        "--- Zone 4/4: zone_d (-3.50, -3.00) ---", "No survivor found at zone_d.",
        "All zones visited. Returning to base.", "Reached base station.", "Mission complete.",
    ]
    positions = [output.find(line) for line in expected]
    assert all(p >= 0 for p in positions), output
    assert positions == sorted(positions), output
    assert "Detection request for zone_a: FOUND at (-2.50, 3.20)" in detect.output
    assert "Detection request for zone_b: no survivor" in detect.output
    assert "Report received: survivor_1 at (-2.50, 3.20). Acknowledged." in report.output
    assert "Report received: survivor_2 at (4.10, -2.50). Acknowledged." in report.output
    assert nav.output.count("goal x=") == 5, "four zones and one base goal, never re-sent"
    assert [json.loads(line)["survivor_id"] for line in reports.read_text().splitlines()] == [
        "survivor_1", "survivor_2"]
    doc = json.loads(status.read_text())
    assert doc["status"] == "SUCCESS"
    assert doc["nodes"]["0"] == "SUCCESS"
    assert [e.message for e in verdicts(status) if e.node_name == "LogNoDetection"] == [
        "No survivor found at zone_b.", "No survivor found at zone_d."]
    assert reasons(status) == []
    told = [(e.kind, e.value("zone_id"), e.value("survivor_id"))
            for e in read_events(status.with_name(EVENTS_FILE))
            if e.kind in (SarKind.ZONE_REACHED, SarKind.SURVIVOR_REPORTED,
                          SarKind.BASE_REACHED)]
    assert told == [
        (SarKind.ZONE_REACHED, "zone_a", ""), (SarKind.SURVIVOR_REPORTED, "", "survivor_1"),
        (SarKind.ZONE_REACHED, "zone_b", ""), (SarKind.ZONE_REACHED, "zone_c", ""),
        (SarKind.SURVIVOR_REPORTED, "", "survivor_2"), (SarKind.ZONE_REACHED, "zone_d", ""),
        (SarKind.BASE_REACHED, "", "")]
