"""A testing kit for plugin authors (and this project's own tests).

Installing sar_framework registers :mod:`sar_framework.testing.pytest_plugin` with
pytest, so a plugin package's tests get the fixtures ``sar_tree``, ``sar_leaf``,
``sar_ros_domain``, ``sar_ros_node`` and ``sar_mission_stack`` with no conftest::

    from sar_framework.testing import assert_feedback, assert_statuses

    def test_countdown_finishes(sar_leaf):
        run = sar_leaf("Countdown", {"ticks": 2})
        run.tick(3)
        assert_statuses(run, ["RUNNING", "RUNNING", "SUCCESS"])
        assert_feedback(run, "done")            # a regular expression, searched
        assert_feedback_text(run, "done")       # plain text
        run.entries()                           # the tree's blackboard entries

Modules: :mod:`.trees` (load YAML text, tick, record), :mod:`.assertions`,
:mod:`.ros_env` (a private ROS domain), :mod:`.spin` (rclpy node and bounded spinning),
:mod:`.ros_harness` (trees set up on a node, ticking with spinning, probes),
:mod:`.processes` (ROS nodes as child processes), :mod:`.mission_stack` (the embedded
simulator and the installed apps' processes), :mod:`.nav2_navigators` (Nav2's navigator trees
imported and run one after another against one simulator, reset between runs). Only the
ROS modules import ROS, lazily.
"""

from sar_framework.testing.assertions import (
    assert_feedback,
    assert_feedback_text,
    assert_status,
    assert_statuses,
)
from sar_framework.testing.trees import (
    TickRecord,
    TreeRun,
    declared_leaf,
    leaf_run,
    tree_from_yaml,
)

__all__ = ["TickRecord", "TreeRun", "assert_feedback", "assert_feedback_text", "assert_status",
           "assert_statuses", "declared_leaf", "leaf_run", "tree_from_yaml"]
