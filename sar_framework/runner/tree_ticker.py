"""The tree wrapper the runner ticks: ``py_trees_ros.trees.BehaviourTree`` or a fallback.

This module alone decides which one. With ``py_trees_ros`` importable (a real ROS
install, version >= 2.2 where ``setup`` accepts ``node=``) its BehaviourTree is used, so
the tree shows up in ``py-trees-tree-watcher``. Otherwise :class:`FallbackBehaviourTree`
offers the same surface the runner uses::

    tree = create_behaviour_tree(root)
    tree.setup(node=node, timeout=15.0)      # every behaviour's setup(node=node)
    tree.tick_tock(period_ms=500.0)          # a timer on the node: ROS time, /clock aware
    ...                                      # spin the node's executor
    tree.shutdown()                          # timer, behaviours' shutdown(), the node

Both tick on a timer of the node (so ticks interleave with the executor's other
callbacks, and follow ``/clock`` when ``use_sim_time`` is set), and both destroy the node
in ``shutdown()``.
"""

from __future__ import annotations

import functools
import inspect
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import py_trees

if TYPE_CHECKING:
    from rclpy.node import Node
    from rclpy.timer import Timer

TickHandler = Callable[[py_trees.trees.BehaviourTree], None]


class FallbackBehaviourTree(py_trees.trees.BehaviourTree):
    """The part of ``py_trees_ros.trees.BehaviourTree`` the runner needs, in plain rclpy.

    Args:
        root: The root behaviour.
    """

    def __init__(self, root: py_trees.behaviour.Behaviour) -> None:
        super().__init__(root)
        self.node: Node | None = None
        self.timer: Timer | None = None
        self.tick_tock_count = 0

    def setup(self, node: Node | None = None, timeout: float = py_trees.common.Duration.INFINITE,
              visitor: py_trees.visitors.VisitorBase | None = None, **kwargs: Any) -> None:
        """Set up every behaviour with ``node=node`` (bounded by ``timeout`` seconds).

        Args:
            node: The ROS node the behaviours use.
            timeout: Seconds; ``py_trees.common.Duration.INFINITE`` to wait forever.
            visitor: Run on each behaviour after its setup.
            **kwargs: Passed on to every behaviour's ``setup``.

        Raises:
            ValueError: Without a node.
            RuntimeError: The setup timed out (raised by py_trees).
        """
        if node is None:
            raise ValueError("FallbackBehaviourTree.setup needs node=")
        self.node = node
        super().setup(timeout=timeout, visitor=visitor, node=node, **kwargs)

    def tick_tock(self, period_ms: float,
                  number_of_iterations: int = py_trees.trees.CONTINUOUS_TICK_TOCK,
                  pre_tick_handler: TickHandler | None = None,
                  post_tick_handler: TickHandler | None = None) -> None:
        """Tick on a ROS timer of the node every ``period_ms`` until told to stop.

        Returns at once; the ticks happen while the node's executor spins.

        Args:
            period_ms: Milliseconds between ticks.
            number_of_iterations: Stop after this many ticks (default: never).
            pre_tick_handler: Run before each tick.
            post_tick_handler: Run after each tick.

        Raises:
            RuntimeError: Before :meth:`setup`.
        """
        if self.node is None:
            raise RuntimeError("call setup(node=...) before tick_tock()")
        self.tick_tock_count = 0
        self.timer = self.node.create_timer(
            period_ms / 1000.0,
            functools.partial(self._on_timer, number_of_iterations, pre_tick_handler,
                              post_tick_handler),
        )

    def _on_timer(self, number_of_iterations: int, pre_tick_handler: TickHandler | None,
                  post_tick_handler: TickHandler | None) -> None:
        if (number_of_iterations != py_trees.trees.CONTINUOUS_TICK_TOCK
                and self.tick_tock_count >= number_of_iterations):
            if self.timer is not None:
                self.timer.cancel()
            return
        self.tick(pre_tick_handler, post_tick_handler)
        self.tick_tock_count += 1

    def shutdown(self) -> None:
        """Stop the timer, shut every behaviour down, then destroy the node."""
        if self.node is not None and self.timer is not None:
            self.timer.cancel()
            self.node.destroy_timer(self.timer)
            self.timer = None
        super().shutdown()
        if self.node is not None:
            self.node.destroy_node()


def ros_behaviour_tree_class() -> type | None:
    """Return ``py_trees_ros.trees.BehaviourTree`` when importable and new enough, else None.

    "New enough" means its ``setup`` accepts an existing ``node`` (py_trees_ros >= 2.2);
    older versions create a node of their own, which would not see the runner's parameters.
    """
    try:
        from py_trees_ros.trees import BehaviourTree
    except ImportError:
        return None
    if "node" not in inspect.signature(BehaviourTree.setup).parameters:
        return None
    return BehaviourTree


def create_behaviour_tree(root: py_trees.behaviour.Behaviour, *,
                          prefer_ros: bool = True) -> py_trees.trees.BehaviourTree:
    """Wrap ``root`` in the best available ticking tree.

    Args:
        root: The root behaviour.
        prefer_ros: Use py_trees_ros when it is available.

    Returns:
        A ``py_trees_ros.trees.BehaviourTree`` or a :class:`FallbackBehaviourTree`.
    """
    cls = ros_behaviour_tree_class() if prefer_ros else None
    if cls is not None:
        return cls(root, unicode_tree_debug=False)
    return FallbackBehaviourTree(root)


def publish_snapshots(tree: py_trees.trees.BehaviourTree) -> None:
    """Publish the tree's snapshot streams as they stand, without ticking.

    A finished mission kept alive is not ticked again; py_trees_ros publishes snapshots
    only after a tick, so without this a watcher that connects later sees nothing. Each
    stream keeps its own period. Nothing to do for the fallback, which has no streams.
    """
    streams = getattr(tree, "snapshot_streams", None)
    if not streams:
        return
    for stream in list(streams.values()):
        stream.publish(root=tree.root, changed=False, statistics=tree.statistics,
                       visited_behaviour_ids=tree.snapshot_visitor.visited.keys(),
                       visited_blackboard_client_ids=(
                           tree.snapshot_visitor.visited_blackboard_client_ids))


def snapshot_topics(tree: py_trees.trees.BehaviourTree) -> list[str]:
    """The topics of the tree's open snapshot streams (none for the fallback)."""
    streams = getattr(tree, "snapshot_streams", None) or {}
    return [stream.publisher.topic_name for stream in list(streams.values())]


def implementation_name(tree: py_trees.trees.BehaviourTree) -> str:
    """Name the wrapper in use, for the log: ``py_trees_ros`` or ``fallback``."""
    return "fallback" if isinstance(tree, FallbackBehaviourTree) else "py_trees_ros"
