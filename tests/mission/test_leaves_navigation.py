"""NavigateToZone / NavigateToBase against a real NavigateToPose server in another process.

The fake server (tests/sar_testing/nodes/scripted_navigate_server.py) lets each goal pick
its outcome through the goal's ``behavior_tree`` field, which the leaves pass through
from their ``behavior_tree`` param: succeed, abort, reject or hang.
"""

from __future__ import annotations

import re
from collections.abc import Iterator

import py_trees
import pytest
from py_trees.common import OneShotPolicy, Status
from sar_plugins.sar.leaves.navigate_to_base import NavigateToBase
from sar_plugins.sar.leaves.navigate_to_zone import NavigateToZone
from sar_testing.leaf_harness import (
    BASE,
    NODES,
    OutputMark,
    TreeMaker,
    ros_seconds,
    spec_zone_manager,
    tick_until_done,
    tree_on,
    wait_for_action_server,
)
from sar_testing.processes import NodeProcess
from sar_testing.spin import spin_until

from sar_framework.testing import declared_leaf

pytestmark = pytest.mark.ros

LEAF_RUN_S = 60.0
"""Outer safety bound of a leaf's run (well under a second expected, even under load)."""
GOAL = re.compile(r"goal \d+: x=(\S+) y=(\S+) qz=(\S+) qw=(\S+) frame=(\S+) script=(\S+)")


@pytest.fixture(scope="module")
def nav_server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[NodeProcess]:
    """One scripted NavigateToPose server for the whole module (goals pick their outcome)."""
    log_dir = tmp_path_factory.mktemp("nav")
    with NodeProcess([str(NODES / "scripted_navigate_server.py"), "--delay", "0.3"], "nav",
                     log_dir=log_dir) as server:
        server.wait_for_output("ready")
        yield server


@pytest.fixture
def nav(module_ros: tuple, nav_server: NodeProcess) -> Iterator[tuple]:
    """``(make_tree, executor, mark)``: the server discovered, its output marked."""
    node, executor = module_ros
    wait_for_action_server(node, executor)
    make_tree = TreeMaker(node)
    yield make_tree, executor, OutputMark(nav_server)
    make_tree.shutdown()


def goals(text: str) -> list[tuple[str, ...]]:
    return GOAL.findall(text)


def test_success_sends_the_zone_pose_and_logs_the_spec_lines(nav: tuple,
                                                             capfd: pytest.CaptureFixture) -> None:
    make_tree, executor, mark = nav
    leaf = declared_leaf(NavigateToZone, "NavigateToZone", zone_manager=spec_zone_manager())
    tree = make_tree(leaf)

    status = tick_until_done(executor, tree, LEAF_RUN_S)
    assert status == Status.SUCCESS, f"{leaf.feedback_message}; the server said:\n{mark.text}"
    assert leaf.feedback_message == "Reached zone_a."
    assert goals(mark.text) == [("-3.00", "3.00", "0.000", "1.000", "map", "succeed")]
    err = capfd.readouterr().err
    assert "--- Zone 1/4: zone_a (-3.00, 3.00) ---" in err
    assert "Reached zone_a." in err

    # A finished goal is not cancelled when the leaf is reset afterwards.
    leaf.stop(Status.INVALID)
    spin_until(executor, lambda: False, 0.5)
    assert "cancel requested" not in mark.text


def test_a_goal_whose_answer_is_lost_is_sent_once_more(nav: tuple,
                                                     capfd: pytest.CaptureFixture) -> None:
    """A goal the server answers only after the next one came (to the leaf, a lost answer)
    is sent again after the acceptance bound; the late first goal is cancelled, and the zone
    is announced once."""
    make_tree, executor, mark = nav
    leaf = declared_leaf(NavigateToZone, "NavigateToZone", zone_manager=spec_zone_manager(),
                          behavior_tree="answer-after-next")
    leaf.ack_timeout_wall_s = 0.2  # the shipped 5 s would only make the test longer
    tree = make_tree(leaf)

    status = tick_until_done(executor, tree, LEAF_RUN_S)
    assert status == Status.SUCCESS, f"{leaf.feedback_message}; the server said:\n{mark.text}"
    assert leaf.feedback_message == "Reached zone_a."
    sent = ("-3.00", "3.00", "0.000", "1.000", "map", "answer-after-next")
    assert goals(mark.text) == [sent, sent]
    assert spin_until(executor, lambda: "goal canceled" in mark.text, LEAF_RUN_S), mark.text
    err = capfd.readouterr().err
    assert err.count("--- Zone 1/4: zone_a (-3.00, 3.00) ---") == 1
    assert "navigate_to_pose did not accept the goal within 0.2 s; sending it again" in err


@pytest.mark.parametrize(("behavior_tree", "why", "server_says"), [
    ("abort", "aborted: robot stuck", "goal aborted"),
    ("reject", "rejected by navigate_to_pose", "script=reject"),
])
def test_an_aborted_or_rejected_goal_fails_saying_why(nav: tuple, behavior_tree: str, why: str,
                                                      server_says: str) -> None:
    make_tree, executor, mark = nav
    leaf = declared_leaf(NavigateToZone, "NavigateToZone", zone_manager=spec_zone_manager(),
                          behavior_tree=behavior_tree)
    tree = make_tree(leaf)

    assert tick_until_done(executor, tree, LEAF_RUN_S) == Status.FAILURE
    assert leaf.feedback_message == f"goal to zone_a {why}"
    assert len(goals(mark.text)) == 1 and server_says in mark.text


def test_goal_that_never_finishes_fails_after_its_bound_and_is_cancelled(nav: tuple) -> None:
    make_tree, executor, mark = nav
    leaf = declared_leaf(NavigateToZone, "NavigateToZone", zone_manager=spec_zone_manager(),
                          behavior_tree="hang", navigation_timeout_s=1.0)
    tree = make_tree(leaf)

    start = ros_seconds()
    assert tick_until_done(executor, tree, LEAF_RUN_S) == Status.FAILURE
    assert ros_seconds() - start >= 1.0  # the leaf's bound counts ROS time
    assert leaf.feedback_message == ("navigation to zone_a not finished within 1.0 s; "
                                     "goal cancelled")
    assert spin_until(executor, lambda: "goal canceled" in mark.text, 5.0), mark.text


def test_missing_server_keeps_running_then_fails_after_its_bound(ros: tuple) -> None:
    node, executor = ros
    leaf = declared_leaf(NavigateToZone, "NavigateToZone", zone_manager=spec_zone_manager(),
                          action_name="no_such_navigate", server_timeout_s=1.0)
    tree = tree_on(node, leaf)

    start = ros_seconds()
    tree.tick()
    assert leaf.status == Status.RUNNING
    assert tick_until_done(executor, tree, LEAF_RUN_S) == Status.FAILURE
    assert ros_seconds() - start >= 1.0  # the leaf's bound counts ROS time
    assert leaf.feedback_message == "no_such_navigate server not available after 1.0 s"


def test_second_zone_sends_a_fresh_goal(nav: tuple) -> None:
    make_tree, executor, mark = nav
    zones = spec_zone_manager()
    leaf = declared_leaf(NavigateToZone, "NavigateToZone", zone_manager=zones)
    tree = make_tree(leaf)
    assert tick_until_done(executor, tree, LEAF_RUN_S) == Status.SUCCESS

    zones.advance()
    tree.tick()
    assert leaf.status == Status.RUNNING, "the previous verdict leaked into the new goal"
    assert tick_until_done(executor, tree, LEAF_RUN_S) == Status.SUCCESS
    assert leaf.feedback_message == "Reached zone_b."
    sent = goals(mark.text)
    assert len(sent) == 2
    assert sent[1][:4] == ("3.50", "3.00", "0.707", "0.707")  # yaw 1.57 about z


def test_halting_the_tree_mid_goal_cancels_it(nav: tuple) -> None:
    make_tree, executor, mark = nav
    leaf = declared_leaf(NavigateToZone, "NavigateToZone", zone_manager=spec_zone_manager(),
                          behavior_tree="hang")
    root = py_trees.composites.Sequence("Patrol", memory=True, children=[leaf])
    tree = make_tree(root)
    tree.tick()
    assert spin_until(executor, lambda: "accepted" in leaf.feedback_message
                      or "navigating" in leaf.feedback_message, 5.0, step=tree.tick)
    assert root.status == Status.RUNNING

    tree.root.stop(Status.INVALID)
    assert spin_until(executor, lambda: "goal canceled" in mark.text, 5.0), mark.text
    assert "cancel requested" in mark.text
    assert leaf.feedback_message == "navigation to zone_a interrupted; goal cancelled"


def test_base_goal_is_sent_once_under_a_reactive_selector(nav: tuple,
                                                          capfd: pytest.CaptureFixture) -> None:
    make_tree, executor, mark = nav
    zones = spec_zone_manager()
    while zones.has_remaining():
        zones.mark_reached(zones.current_zone()["id"])
        zones.advance()
    from sar_plugins.sar.leaves.zones_remaining import ZonesRemaining

    patrol = py_trees.composites.Sequence("Patrol", memory=True,
                                          children=[ZonesRemaining("ZonesRemaining?",
                                                                   zone_manager=zones)])
    base = declared_leaf(NavigateToBase, "NavigateToBase", zone_manager=zones)
    oneshot = py_trees.decorators.OneShot(name="NavigateToBaseOneShot", child=base,
                                          policy=OneShotPolicy.ON_COMPLETION)
    root = py_trees.composites.Selector("MissionOrReturnToBase", memory=False,
                                        children=[patrol, oneshot])
    tree = make_tree(root)

    assert tick_until_done(executor, tree, LEAF_RUN_S) == Status.SUCCESS
    for _ in range(50):
        executor.spin_once(timeout_sec=0.02)
        tree.tick()
        assert root.status == Status.SUCCESS
    assert goals(mark.text) == [(f"{BASE['x']:.2f}", f"{BASE['y']:.2f}", "0.000", "1.000",
                                 "map", "succeed")]
    err = capfd.readouterr().err
    assert err.count("All zones visited. Returning to base.") == 1
    assert err.count("Reached base station.") == 1


def test_the_base_goal_names_the_zones_not_reached(nav: tuple,
                                                   capfd: pytest.CaptureFixture) -> None:
    """Regression: 'All zones visited.' was logged although a zone had been skipped."""
    make_tree, executor, _mark = nav
    zones = spec_zone_manager()
    while zones.has_remaining():
        if zones.current_zone()["id"] != "zone_b":
            zones.mark_reached(zones.current_zone()["id"])
        zones.advance()
    tree = make_tree(declared_leaf(NavigateToBase, "NavigateToBase", zone_manager=zones))
    assert tick_until_done(executor, tree, LEAF_RUN_S) == Status.SUCCESS
    err = capfd.readouterr().err
    assert "Zones done, not reached: zone_b. Returning to base." in err
    assert "All zones visited" not in err


def test_halting_before_the_goal_is_accepted_still_cancels_it(nav: tuple) -> None:
    make_tree, executor, mark = nav
    leaf = declared_leaf(NavigateToZone, "NavigateToZone", zone_manager=spec_zone_manager(),
                          behavior_tree="hang")
    tree = make_tree(leaf)
    tree.tick()  # the goal is sent; its acceptance has not been spun in yet
    assert leaf.status == Status.RUNNING
    leaf.stop(Status.INVALID)
    assert spin_until(executor, lambda: "goal canceled" in mark.text, 5.0), mark.text
    assert len(goals(mark.text)) == 1
