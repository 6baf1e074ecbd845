"""The watcher's snapshot feed against a real py_trees_ros tree and its snapshot stream."""

from __future__ import annotations

import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import py_trees
import pytest
from sar_testing.spin import ros_node, spin_until

from sar_framework import load_tree
from sar_framework.runner.tree_status import STATUS_TOPIC, TreeStatusPublisher, decode_status
from sar_framework.watch.snapshot_source import SnapshotFeed

pytestmark = pytest.mark.ros
trees = pytest.importorskip("py_trees_ros.trees", reason="py_trees_ros is not installed")

HERE = Path(__file__).resolve().parent
TREE_FILE = HERE / "watched.yaml"
COMPARED = ("uid", "name", "status", "message", "visited", "depth")


@dataclass
class Streamed:
    """A py_trees_ros tree on a runner node, its status documents and a watcher's feed."""

    tree: Any
    runner: Any
    executor: Any
    feed: SnapshotFeed
    documents: list[dict]


@pytest.fixture
def streamed() -> Iterator[Streamed]:
    from rclpy.node import Node
    from std_msgs.msg import String

    py_trees.blackboard.Blackboard.clear()
    loaded = load_tree(TREE_FILE, plugin_paths=[HERE / "watch_leaves.py"])
    with ros_node("sar_tree_watch") as (watcher, executor):
        runner = Node("snap_runner", context=watcher.context)
        executor.add_node(runner)
        documents: list[dict] = []
        watcher.create_subscription(String, STATUS_TOPIC,
                                    lambda m: documents.append(decode_status(m.data)), 10)
        tree = trees.BehaviourTree(loaded.root, unicode_tree_debug=False)
        # the runner's order: status publisher first, py_trees_ros's setup after
        TreeStatusPublisher(runner, loaded.spec, loaded.behaviours).attach(tree)
        tree.setup(node=runner, timeout=10.0)
        feed = SnapshotFeed(watcher)
        assert spin_until(executor, lambda: bool(feed.topic), 15.0,
                          step=lambda: feed.poll(time.monotonic() + 1.0))
        yield Streamed(tree, runner, executor, feed, documents)
        executor.remove_node(runner)
        tree.shutdown()


def test_snapshots_and_status_documents_agree_tick_by_tick(streamed: Streamed) -> None:
    tree, runner, executor = streamed.tree, streamed.runner, streamed.executor
    feed, documents = streamed.feed, streamed.documents
    assert feed.service == "/snap_runner/snapshot_streams/open"
    assert feed.topic.startswith("/snap_runner/snapshot_streams/")
    for tick in (1, 2, 3):
        tree.tick()
        assert spin_until(executor, lambda t=tick: feed.has(t) and len(documents) >= t, 10.0)
    for document in documents:
        snapshot = feed.snapshots[document["tick"]]
        assert ([[n[k] for k in COMPARED] for n in snapshot["nodes"]]
                == [[n[k] for k in COMPARED] for n in document["nodes"]])
        merged = feed.merged(document)
        assert merged["nodes"] == document["nodes"]  # kinds kept from the status
        assert merged["blackboard"] == document["blackboard"]
    statuses = [[n["status"] for n in feed.snapshots[t]["nodes"]] for t in (1, 2, 3)]
    assert statuses == [["RUNNING", "FAILURE", "RUNNING", "RUNNING", "INVALID"],
                        ["RUNNING", "FAILURE", "RUNNING", "RUNNING", "INVALID"],
                        ["SUCCESS", "FAILURE", "SUCCESS", "SUCCESS", "SUCCESS"]]
    assert feed.snapshots[3]["blackboard"] == {"/ticks_counted": "1"}
    topic = feed.topic
    feed.close(executor)
    assert spin_until(executor, lambda: runner.count_publishers(topic) == 0, 5.0)


def test_the_last_snapshot_is_awaited_until_it_comes_or_the_stream_ends(
        streamed: Streamed) -> None:
    """However late a tick's snapshot is, the watcher waits for it or for the stream's end."""
    from sar_framework.runner.tree_ticker import snapshot_topics

    tree, executor, feed = streamed.tree, streamed.executor, streamed.feed
    # the runner delivers its open streams before it leaves, as it does its status
    assert snapshot_topics(tree) == [feed.topic]
    assert not feed.settled(1)
    assert not feed.ended()
    tree.tick()
    assert spin_until(executor, lambda: feed.settled(1), 10.0), sorted(feed.snapshots)
    assert feed.has(1)
    assert not feed.settled(2)  # the stream is open: tick 2's snapshot may still come
    feed.close(executor)
    assert spin_until(executor, feed.ended, 10.0), "the stream's publisher is still there"
    assert feed.settled(2) and not feed.has(2)
    assert snapshot_topics(tree) == []


def test_merge_takes_statuses_from_the_snapshot_and_kinds_from_the_status() -> None:
    from sar_framework.watch.snapshot_source import merge

    document = {"tick": 4, "nodes": [{"uid": "0", "name": "Root", "kind": "selector",
                                      "status": "RUNNING", "message": "", "visited": True,
                                      "depth": 0}], "blackboard": {"/k": "1"}}
    snapshot = {"tick": 4, "nodes": [{**document["nodes"][0], "kind": "Selector",
                                      "status": "SUCCESS"}], "blackboard": {"/k": "2", "/x": "3"}}
    merged = merge(document, snapshot)
    assert merged["nodes"][0]["status"] == "SUCCESS" and merged["nodes"][0]["kind"] == "selector"
    assert merged["blackboard"] == {"/k": "2"}
    feed = SnapshotFeed(node=None)  # no snapshot yet: the status document as it is
    assert feed.merged(document) is document
    feed.snapshots[5] = snapshot
    assert feed.merged(document) is document  # another tick's snapshot is not used
    feed.snapshots[4] = snapshot
    assert feed.merged(document)["nodes"][0]["status"] == "SUCCESS"
