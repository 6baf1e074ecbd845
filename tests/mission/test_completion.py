"""How a mission ends (``completion``): at the tree's declared end, never restarted (no ROS).

Each shape is ticked for real (py_trees, the runner's StatusFileWriter) the way the runner
ticks it: until the recorder says the mission is complete, then never again.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import py_trees
import pytest
from py_trees.common import Status
from sar_plugins.sar.zone_manager import ZoneManager
from sar_testing.manual_clock import ManualClock

from sar_framework import load_spec, load_tree
from sar_framework.engine.building.control_build import CLOCK_KEY
from sar_framework.mission.completion import (
    describe_completion,
    ending_one_shot,
    resolve_completion,
)
from sar_framework.runner.status_file import StatusFileWriter

REPO = Path(__file__).resolve().parents[2]
PLUGINS = Path(__file__).resolve().parent / "runner_plugins"

# The last child of both mission shapes below: home, once.
HOME_ONCE = """\
      - one_shot:
          name: HomeOnce
          policy: on_completion
          child: {Countdown: {name: Home, ticks: 2}}
"""

# The user's trial tree: a time budget around a repeat over the zones, then one_shot home.
BUDGET_THEN_HOME = """\
format: 1
name: budget_then_home
root:
  sequence:
    name: Mission
    memory: true
    children:
      - failure_is_success:
          name: BudgetOver
          child:
            timeout:
              name: Budget
              duration: 6
              child:
                repeat:
                  num_success: -1
                  child: {Countdown: {name: Patrol, ticks: 1}}
""" + HOME_ONCE

# The reference tree's shape: a reactive root, a memory patrol, one_shot home last.
REFERENCE_SHAPE = """\
format: 1
name: reference_shape
root:
  selector:
    name: MissionOrReturnToBase
    memory: false
    children:
      - sequence:
          name: Patrol
          memory: true
          children:
            - ZonesRemaining: {}
            - Countdown: {name: Visit, ticks: 1}
            - AdvanceZone: {}
""" + HOME_ONCE

TICK_FOREVER = """\
format: 1
name: tick_forever
root:
  repeat:
    num_success: -1
    child: {Countdown: {name: Patrol, ticks: 1}}
"""


def run(tmp_path: Path, text: str, *, mode: str = "auto", ticks: int = 60,
        after: int = 0) -> tuple[StatusFileWriter, list[str], ManualClock]:
    """Tick like the runner: stop once complete; then ``after`` post-tick calls (keep-alive).

    Returns the recorder, the names of the leaves each time they started, and the clock.
    """
    path = tmp_path / "tree.yaml"
    path.write_text(text)
    zones = ZoneManager([{"id": z, "x": 0.0, "y": 0.0, "yaw": 0.0} for z in ("a", "b", "c")],
                        {"x": 0.0, "y": 0.0, "yaw": 0.0})
    clock = ManualClock(100.0)
    loaded = load_tree(path, context={"zone_manager": zones, CLOCK_KEY: clock},
                       plugin_paths=[PLUGINS])
    effective = resolve_completion(mode, loaded.spec)[0]
    recorder = StatusFileWriter(str(path), loaded.spec, loaded.behaviours, clock,
                              completion=effective,
                              end_uid=getattr(ending_one_shot(loaded.spec), "uid", None))
    tree = py_trees.trees.BehaviourTree(loaded.root)
    started: list[str] = []

    class Starts(py_trees.visitors.VisitorBase):
        def run(self, behaviour: py_trees.behaviour.Behaviour) -> None:
            if not behaviour.children and behaviour.status == Status.RUNNING \
                    and (not started or started[-1] != behaviour.name
                         or behaviour.name not in running):
                started.append(behaviour.name)
            if behaviour.status == Status.RUNNING:
                running.add(behaviour.name)
            else:
                running.discard(behaviour.name)

    running: set[str] = set()
    tree.visitors += [recorder, Starts()]
    tree.add_post_tick_handler(recorder.after_tick)
    for _ in range(ticks):
        clock.now += 1.0
        tree.tick()
        if recorder.complete:
            break  # what the runner does: a complete mission is not ticked again
    for _ in range(after):
        clock.now += 1.0
        recorder.after_tick(tree)
    return recorder, started, clock


def test_budget_then_home_ends_when_home_latches_and_never_patrols_again(tmp_path: Path) -> None:
    """Regression: 'auto' chose 'rest'; the tick after home restarted the whole patrol."""
    recorder, started, _ = run(tmp_path, BUDGET_THEN_HOME)
    assert recorder.complete and recorder.status == Status.SUCCESS
    assert started.count("Home") == 1
    assert "Patrol" not in started[started.index("Home"):]  # not sent off again


def test_the_reference_shape_ends_at_its_one_shot_not_after_the_first_zone(tmp_path: Path
                                                                         ) -> None:
    recorder, started, _ = run(tmp_path, REFERENCE_SHAPE)
    assert recorder.complete and recorder.status == Status.SUCCESS
    assert started.count("Visit") == 3 and started.count("Home") == 1
    assert started[-1] == "Home"


def test_a_tick_forever_tree_is_never_complete_by_default(tmp_path: Path) -> None:
    recorder, started, _ = run(tmp_path, TICK_FOREVER, ticks=40)
    assert not recorder.complete and recorder.ticks == 40
    assert started.count("Patrol") >= 10


def test_a_tree_file_declares_forever_and_the_parameter_overrides_it(tmp_path: Path) -> None:
    text = REFERENCE_SHAPE.replace("name: reference_shape", "name: r\ncompletion: forever")
    recorder, _, _ = run(tmp_path, text, ticks=30)
    assert not recorder.complete and recorder.ticks == 30
    spec = load_spec(tmp_path / "tree.yaml", plugin_paths=[PLUGINS])
    assert describe_completion("auto", spec) == (
        "completion: forever (declared in the tree file; ticked until Ctrl-C)")
    assert resolve_completion("once", spec)[0] == "once"


def test_keep_alive_freezes_the_figures_at_completion(tmp_path: Path) -> None:
    """Regression: a mission kept alive counted on (822.8 s simulated, 1,629 ticks)."""
    frozen = run(tmp_path, BUDGET_THEN_HOME)[0].document()
    recorder2, _, clock2 = run(tmp_path, BUDGET_THEN_HOME, after=50)
    later = recorder2.document()
    assert later["ticks"] == frozen["ticks"] and later["sim_end_s"] == frozen["sim_end_s"]
    assert clock2.now - later["sim_end_s"] == 50.0
    assert later["complete"] and later["status"] == "SUCCESS"


@pytest.mark.parametrize("tree", ["trees/search_and_rescue.yaml",
                                  "trees/examples/bounded_mission.yaml",
                                  "trees/examples/patrol_skip_unreachable.yaml"])
def test_shipped_missions_end_when_their_one_shot_latches(tree: str) -> None:
    mode, why = resolve_completion("auto", load_spec(REPO / tree))
    assert mode == "end"
    assert why.startswith("default; the mission ends when the tree reaches its declared end: "
                          "when one_shot NavigateToBaseOneShot")


def test_a_tree_without_a_one_shot_ends_at_the_roots_first_verdict(tmp_path: Path) -> None:
    path = tmp_path / "t.yaml"
    path.write_text(TICK_FOREVER)
    spec = load_spec(path, plugin_paths=[PLUGINS])
    assert describe_completion("auto", spec).endswith(
        "the root's first SUCCESS or FAILURE (no one_shot on its final path))")
    assert describe_completion("rest", spec) == (
        "completion: rest (set in the parameters; the mission ends when the tree is at rest)")
    with pytest.raises(ValueError, match="auto, end, once, rest, forever"):
        resolve_completion("terminal", spec)


def validate_command(path: Path) -> subprocess.CompletedProcess[str]:
    """``sar-tree validate`` of ``path`` with the runner's test plugins."""
    return subprocess.run([sys.executable, "-m", "sar_framework", "validate", str(path),
                           "--plugin-path", str(PLUGINS)], capture_output=True, text=True,
                          check=False)


def test_validate_prints_what_applies(tmp_path: Path) -> None:
    path = tmp_path / "t.yaml"
    path.write_text(BUDGET_THEN_HOME.replace("name: budget_then_home",
                                             "name: b\ncompletion: once"))
    done = validate_command(path)
    assert done.returncode == 0, done.stderr
    assert done.stdout == f"{path}: ok (7 nodes; completion: once, declared in the tree file)\n"


def test_a_bad_completion_key_is_reported_with_its_place(tmp_path: Path) -> None:
    path = tmp_path / "t.yaml"
    path.write_text(TICK_FOREVER.replace("name: tick_forever", "name: t\ncompletion: restt"))
    done = validate_command(path)
    assert done.returncode == 1
    assert "t.yaml:3:13: error: 'completion' must be one of: end, once, rest, forever; " \
        "got string 'restt' (did you mean 'rest'?)" in done.stderr
