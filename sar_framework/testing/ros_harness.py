"""ROS helpers for testing leaves: trees set up on a node, ticking with spinning, probes.

Ticks are driven the way the runner drives them: one thread, ``executor.spin_once``
interleaved with ``tree.tick()``; nothing blocks on a future.
"""

from __future__ import annotations

from typing import Any

import py_trees
from py_trees.common import Status

from sar_framework.events.emitter import SETUP_KEY, EventEmitter
from sar_framework.testing.spin import spin_until

DISCOVERY_S = 15.0  # discovery across processes takes ~1-3 s; leave room on a loaded machine
TERMINAL = (Status.SUCCESS, Status.FAILURE)


def tree_on(node: Any, root: py_trees.behaviour.Behaviour,
            events: EventEmitter | None = None) -> py_trees.trees.BehaviourTree:
    """Wrap ``root`` in a BehaviourTree and set it up with the ROS node, py_trees_ros style.

    Args:
        node: The ROS node.
        root: The tree's root.
        events: An emitter to give the leaves, as the runner does (its ``emitted`` list
            holds what they said); none by default.
    """
    tree = py_trees.trees.BehaviourTree(root)
    extra = {} if events is None else {SETUP_KEY: events}
    tree.setup(timeout=5.0, node=node, **extra)
    return tree


class TreeMaker:
    """Builds trees set up on one node and shuts them all down at the end of a test.

    Shutting a tree down destroys its leaves' clients, so tests can share a node (and
    its already-finished discovery) without clients piling up on it.

    Args:
        node: The ROS node the trees are set up with.
        events: The emitter the leaves get (see :func:`tree_on`).
    """

    def __init__(self, node: Any, events: EventEmitter | None = None) -> None:
        self._node = node
        self._events = events
        self._trees: list[py_trees.trees.BehaviourTree] = []

    def __call__(self, root: py_trees.behaviour.Behaviour) -> py_trees.trees.BehaviourTree:
        """Return ``root`` as a tree set up on the node."""
        self._trees.append(tree_on(self._node, root, self._events))
        return self._trees[-1]

    def shutdown(self) -> None:
        """Shut every tree built so far down."""
        for tree in self._trees:
            tree.shutdown()
        self._trees.clear()


def tick_until_done(executor: Any, tree: py_trees.trees.BehaviourTree,
                    timeout: float) -> Status:
    """Tick (interleaved with spin_once) until the root is SUCCESS or FAILURE; return it."""
    tree.tick()
    spin_until(executor, lambda: tree.root.status in TERMINAL, timeout, step=tree.tick)
    return tree.root.status


def wait_for_action_server(node: Any, executor: Any, name: str = "navigate_to_pose") -> None:
    """Spin until this node's participant has discovered the NavigateToPose server."""
    from nav2_msgs.action import NavigateToPose
    from rclpy.action import ActionClient

    probe = ActionClient(node, NavigateToPose, name)
    try:
        assert spin_until(executor, probe.server_is_ready, DISCOVERY_S), f"no {name} server"
    finally:
        probe.destroy()


def wait_for_service(node: Any, executor: Any, srv_type: Any, name: str) -> None:
    """Spin until this node's participant has discovered the service ``name``."""
    probe = node.create_client(srv_type, name)
    try:
        assert spin_until(executor, probe.service_is_ready, DISCOVERY_S), f"no {name} service"
    finally:
        node.destroy_client(probe)


class TfStaticRecorder:
    """Records every ``/tf_static`` message a node receives (RELIABLE, TRANSIENT_LOCAL).

    Args:
        node: The node to subscribe with.
    """

    def __init__(self, node: Any) -> None:
        from tf2_msgs.msg import TFMessage

        from sar_framework.ros.qos import tf_static_qos

        self.messages: list[Any] = []
        node.create_subscription(TFMessage, "/tf_static", self.messages.append, tf_static_qos())

    def child_frames(self) -> set[str]:
        """Every child frame id seen in any message."""
        return {t.child_frame_id for m in self.messages for t in m.transforms}


class OutputMark:
    """Reads only what a child process printed after the mark was made.

    Args:
        process: A :class:`sar_framework.testing.processes.NodeProcess`.
    """

    def __init__(self, process: Any) -> None:
        self._process = process
        self._start = len(process.output)

    @property
    def text(self) -> str:
        """The output since the mark."""
        return self._process.output[self._start:]
