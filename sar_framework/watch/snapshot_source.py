"""Node statuses from py_trees_ros's snapshot stream, for ``sar-tree watch``.

With py_trees_ros installed the runner ticks a ``py_trees_ros.trees.BehaviourTree``, which
offers snapshot streams (``~/snapshot_streams/open`` and ``close`` on the runner's node).
:class:`SnapshotFeed` finds the runner as the node publishing ``/sar_tree/status``, opens
a stream there as ``py-trees-tree-watcher`` does (one snapshot per tick, with the
blackboard variables on the visited path; the activity stream is not asked for, the view
does not show it), and :meth:`SnapshotFeed.merged` puts the snapshot's node statuses,
messages and blackboard values into the status document of the same tick, so the view
shows what ``py-trees-tree-watcher`` shows. Apps' fields, tick rate and completion stay those of
``/sar_tree/status``. Without py_trees_ros (:func:`snapshots_available`) the watcher
uses ``/sar_tree/status`` alone.
"""

from __future__ import annotations

import time
from typing import TYPE_CHECKING, Any

from sar_framework.runner.tree_status import STATUS_TOPIC

if TYPE_CHECKING:
    from rclpy.executors import Executor
    from rclpy.node import Node

OPEN_TYPE = "py_trees_ros_interfaces/srv/OpenSnapshotStream"
#: ``py_trees_ros_interfaces/msg/Behaviour`` status constants.
STATUS_NAMES = {1: "INVALID", 2: "RUNNING", 3: "SUCCESS", 4: "FAILURE"}
#: Seconds between looks for the runner's snapshot service.
DISCOVERY_PERIOD_S = 0.5
#: Seconds an open request may go unanswered before it is sent again.
OPEN_RESEND_S = 2.0
#: Snapshots kept, by tick.
KEPT = 50
_ZERO_ID = bytes(16)


def snapshots_available() -> bool:
    """Whether py_trees_ros's interfaces are importable (the real ROS stack)."""
    try:
        import py_trees_ros_interfaces.srv  # noqa: F401
    except ImportError:
        return False
    return True


def snapshot_nodes(message: Any) -> list[dict[str, Any]]:
    """The behaviours of a ``py_trees_ros_interfaces/msg/BehaviourTree``, depth first.

    Args:
        message: The snapshot.

    Returns:
        Node dicts as :func:`~sar_framework.runner.tree_status.decode_status` makes
        them (``uid`` is the path of child indices, ``kind`` the behaviour's class name).
    """
    by_id = {bytes(b.own_id.uuid): b for b in message.behaviours}
    roots = [b for b in message.behaviours if bytes(b.parent_id.uuid) == _ZERO_ID]
    nodes: list[dict[str, Any]] = []
    stack = [(roots[0], "0")] if roots else []
    while stack:
        behaviour, uid = stack.pop()
        nodes.append({"uid": uid, "name": behaviour.name, "kind": behaviour.class_name,
                      "status": STATUS_NAMES.get(behaviour.status, "INVALID"),
                      "message": behaviour.message, "visited": behaviour.is_active,
                      "depth": uid.count(".")})
        children = [by_id[bytes(c.uuid)] for c in behaviour.child_ids if bytes(c.uuid) in by_id]
        stack.extend(reversed([(child, f"{uid}.{i}") for i, child in enumerate(children)]))
    return nodes


def snapshot_document(message: Any) -> dict[str, Any]:
    """``{"tick", "nodes", "blackboard"}`` of one snapshot (tick counted from 1)."""
    return {"tick": int(message.statistics.count) + 1, "nodes": snapshot_nodes(message),
            "blackboard": {kv.key: kv.value for kv in message.blackboard_on_visited_path}}


def merge(document: dict[str, Any], snapshot: dict[str, Any]) -> dict[str, Any]:
    """The status document with the snapshot's nodes and blackboard values.

    Nodes keep the status document's kind where uid and name agree; blackboard keys stay
    the ones the leaves write, valued from the snapshot where it has them.
    """
    kinds = {(n["uid"], n["name"]): n["kind"] for n in document["nodes"]}
    nodes = [{**n, "kind": kinds.get((n["uid"], n["name"]), n["kind"])}
             for n in snapshot["nodes"]]
    blackboard = {key: snapshot["blackboard"].get(key, value)
                  for key, value in (document.get("blackboard") or {}).items()}
    return {**document, "nodes": nodes, "blackboard": blackboard}


class SnapshotFeed:
    """A snapshot stream opened on the runner that publishes ``/sar_tree/status``.

    Call :meth:`poll` from the watcher's loop (it discovers the runner and opens the
    stream without blocking), :meth:`merged` to draw, :meth:`close` at the end.

    Args:
        node: The watcher's node.
        status_topic: The runner's status topic (another namespace's, in a fleet).
    """

    def __init__(self, node: Node, status_topic: str = STATUS_TOPIC) -> None:
        self.node = node
        self.status_topic = status_topic
        self.service = ""
        self.topic = ""
        self.snapshots: dict[int, dict[str, Any]] = {}
        self.fresh = False
        self._client: Any = None
        self._closer: Any = None
        self._opening: Any = None
        self._looked_s = 0.0

    def poll(self, now: float) -> None:
        """Find the runner's snapshot service and open a stream, a step at a time.

        Args:
            now: ``time.monotonic()``; an open request unanswered for
                :data:`OPEN_RESEND_S` is sent again.
        """
        if self.topic:
            return
        if self._opening is not None:
            if self._opening.done():
                self._subscribe(self._opening.result().topic_name)
                return
            if now - self._looked_s < OPEN_RESEND_S:
                return
            # No answer: DDS can drop the reply to a request sent just after discovery.
            self._client.remove_pending_request(self._opening)
            self._opening = None
        if now - self._looked_s < DISCOVERY_PERIOD_S:
            return
        self._looked_s = now
        from py_trees_ros_interfaces.srv import OpenSnapshotStream

        if self._client is None:
            service = self._runner_service("open")
            if service is None:
                return
            self.service = service
            self._client = self.node.create_client(OpenSnapshotStream, service)
        if not self._client.service_is_ready():
            return
        request = OpenSnapshotStream.Request()
        request.parameters.snapshot_period = 0.0  # every tick
        request.parameters.blackboard_data = True
        request.parameters.blackboard_activity = False
        self._opening = self._client.call_async(request)

    def _runner_service(self, verb: str) -> str | None:
        for info in self.node.get_publishers_info_by_topic(self.status_topic):
            namespace = info.node_namespace.rstrip("/")
            name = f"{namespace}/{info.node_name}/snapshot_streams/{verb}"
            if any(n == name for n, _ in self.node.get_service_names_and_types()):
                return name
        return None

    def _subscribe(self, topic: str) -> None:
        from py_trees_ros_interfaces.msg import BehaviourTree
        from py_trees_ros_interfaces.srv import CloseSnapshotStream

        self.topic = topic
        self.node.create_subscription(BehaviourTree, topic, self._take, 100)
        self._closer = self.node.create_client(
            CloseSnapshotStream, self.service.rsplit("/", 1)[0] + "/close")

    def _take(self, message: Any) -> None:
        snapshot = snapshot_document(message)
        self.snapshots[snapshot["tick"]] = snapshot
        while len(self.snapshots) > KEPT:
            del self.snapshots[min(self.snapshots)]
        self.fresh = True

    def has(self, tick: int) -> bool:
        """Whether the snapshot of ``tick`` has come."""
        return tick in self.snapshots

    def ended(self) -> bool:
        """Whether the stream is over: no publisher is left on its topic.

        The runner waits until its snapshots were received before it closes the stream, so
        a snapshot not here once the stream ended will not come.
        """
        return bool(self.topic) and self.node.count_publishers(self.topic) == 0

    def settled(self, tick: int) -> bool:
        """Whether the snapshot of ``tick`` has come or never will (the stream ended)."""
        return self.has(tick) or self.ended()

    def merged(self, document: dict[str, Any]) -> dict[str, Any]:
        """``document`` with the statuses of its tick's snapshot, or as it is until that comes."""
        self.fresh = False
        snapshot = self.snapshots.get(int(document.get("tick", 0)))
        return merge(document, snapshot) if snapshot else document

    def close(self, executor: Executor, timeout_s: float = 1.0) -> None:
        """Close the stream on the runner (if it is still there), waiting at most ``timeout_s``."""
        if self._closer is None or not self._closer.service_is_ready():
            return
        from py_trees_ros_interfaces.srv import CloseSnapshotStream

        future = self._closer.call_async(CloseSnapshotStream.Request(topic_name=self.topic))
        deadline = time.monotonic() + timeout_s
        while not future.done() and time.monotonic() < deadline:
            executor.spin_once(timeout_sec=0.05)
