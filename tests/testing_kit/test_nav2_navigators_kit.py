"""sar_testing.nav2_navigators without a simulator: the trees found, imports, bad input."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml
from py_trees.common import Status

from sar_framework.testing.nav2_navigators import (
    NavigatorRun,
    import_navigator,
    navigator_trees,
)


def test_the_twelve_trees_are_found_where_ros_or_the_overlay_has_them() -> None:
    trees = navigator_trees()
    assert len(trees) == 12
    assert "navigate_to_pose_w_replanning_and_recovery" in trees
    assert all(path.suffix == ".xml" and path.is_file() for path in trees.values())


def test_a_navigator_imports_to_a_tree_file_with_its_goal_declared(tmp_path: Path) -> None:
    xml = navigator_trees()["navigate_w_replanning_time"]
    tree = import_navigator(xml, tmp_path)
    document = yaml.safe_load(tree.read_text())
    assert tree == tmp_path / "navigate_w_replanning_time.yaml"
    assert document["blackboard"]["goal"]["type"] == "geometry_msgs/msg/PoseStamped"


def test_a_bad_tree_fails_the_import_with_the_importers_diagnostics(tmp_path: Path) -> None:
    xml = tmp_path / "bad.xml"
    xml.write_text('<root BTCPP_format="4"><BehaviorTree ID="t">\n'
                   '<ComputePathToPose goal="{goal}" bogus="1"/></BehaviorTree></root>')
    with pytest.raises(AssertionError, match=r"bad\.xml:2:\d+: .*bogus"):
        import_navigator(xml, tmp_path)


def test_a_runs_summary_and_leaf_lists() -> None:
    run = NavigatorRun(status=Status.FAILURE, events=[
        {"name": "FollowPath", "kind": "FollowPath", "status": "FAILURE", "message": "stuck"},
        {"name": "SpinRecovery", "kind": "Spin", "status": "SUCCESS", "message": "done"}],
        reasons=[{"what": "failure", "name": "FollowPath", "message": "stuck"}])
    assert run.failed() == ["FollowPath"] and run.succeeded() == ["SpinRecovery"]
    assert "reason failure: FollowPath: stuck" in run.summary()
