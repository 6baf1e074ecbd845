"""The tree's status per tick on ``/sar_tree/status``, for ``sar-tree watch`` and recordings.

One ``std_msgs/msg/String`` per tick whose ``data`` is a JSON document::

    {"format": 1, "tree": "patrol", "tick": 12, "sim_s": 31.5, "sim_start_s": 4.2,
     "status": "RUNNING", "complete": false,
     "nodes": [["0", "MissionOrReturnToBase", "selector", "RUNNING", "", true], ...],
     "blackboard": {"/goal": "..."},
     "entries": [["goal", "/goal", "PoseStamped(header=...)", "geometry_msgs/msg/PoseStamped",
                  "SetGoal"]], "entries_full": false}

``sim_s`` is the runner's ROS clock after the tick (``/clock`` time with ``use_sim_time``),
``sim_start_s`` the same on the first tick. ``nodes`` lists every node depth first as ``[uid,
name, kind, status, feedback message, visited this tick]`` (a uid's depth is its number of
dots). An app adds fields of its own (:attr:`~sar_framework.app.AppRun.status`, shown
through :attr:`~sar_framework.app.App.status_text`); ``blackboard`` holds the keys the leaves
write, with their values as text.
``complete`` turns true once the mission is over (the runner's own verdict).
``entries`` (only for a tree with blackboard entries, :mod:`.entry_values`) lists the
entries whose value changed since the previous message as ``[name, key, value text, type,
writer]``; ``entries_full`` is true when it lists every entry: on the first message and
whenever a new subscriber has matched since the last one, so a late joiner sees them all.

Plain JSON keeps the topic readable by any ROS 2 tool (``ros2 topic echo``, Foxglove's raw
view) without an interface package of ours; :func:`decode_status` reads it back.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING, Any

import py_trees

from sar_framework.runner.entry_values import EntryTracker

if TYPE_CHECKING:
    from rclpy.node import Node

    from sar_framework.engine.spec import TreeSpec

STATUS_TOPIC_NAME = "sar_tree/status"
"""Relative: a runner in ``/robot1`` publishes ``/robot1/sar_tree/status``."""
STATUS_TOPIC = "/" + STATUS_TOPIC_NAME
"""The same topic in the root namespace (a single robot's runner, the readers' default)."""
STATUS_TYPE = "std_msgs/msg/String"
FORMAT = 1
_BLACKBOARD_TEXT_MAX = 120


def written_blackboard(behaviours: dict[str, py_trees.behaviour.Behaviour]) -> dict[str, str]:
    """The blackboard keys the behaviours may write, with their current values as text.

    Args:
        behaviours: ``uid -> behaviour``.

    Returns:
        ``key -> value text`` (``-`` for a key not set yet), sorted by key.
    """
    keys: set[str] = set()
    for behaviour in behaviours.values():
        for client in getattr(behaviour, "blackboards", ()):
            keys.update(client.write)
            keys.update(client.exclusive)
    storage = py_trees.blackboard.Blackboard.storage
    return {key: (repr(storage[key])[:_BLACKBOARD_TEXT_MAX] if key in storage else "-")
            for key in sorted(keys)}


#: How many of the latest status messages a late subscriber receives.
STATUS_HISTORY = 50


class TreeStatusPublisher(py_trees.visitors.VisitorBase):
    """Publishes the tree's status on :data:`STATUS_TOPIC_NAME` (relative) after every tick.

    Attach it to the ticking tree with :meth:`attach`; it notes the behaviours each tick
    visits (as a visitor) and publishes from a post-tick handler.

    Args:
        node: The node to publish from (the runner's).
        spec: The validated tree.
        behaviours: ``uid -> behaviour`` from ``load_tree``.
        extra: The apps' fields of the document, as they are now.
        complete: Returns whether the mission is over (the runner's verdict).
        entries: The tree's entries; none by default.
    """

    def __init__(self, node: Node, spec: TreeSpec,
                 behaviours: dict[str, py_trees.behaviour.Behaviour], *,
                 extra: Callable[[], Mapping[str, Any]] | None = None,
                 complete: Callable[[], bool] | None = None,
                 entries: EntryTracker | None = None) -> None:
        from std_msgs.msg import String

        from sar_framework.ros.qos import latched_qos

        super().__init__(full=False)
        self._node = node
        self._name = spec.name
        self._order = [(n.uid, n.name, n.kind) for n in spec.nodes()]
        self._behaviours = behaviours
        self._extra = extra or dict
        self._complete = complete or (lambda: False)
        self._visited: set[int] = set()
        self._message_type = String
        # Latched: a recorder or watcher that matches late still gets the last ticks (a
        # finished mission is not ticked again, so nothing newer would come).
        self._publisher = node.create_publisher(String, STATUS_TOPIC_NAME,
                                                latched_qos(STATUS_HISTORY))
        self._entries = entries if entries is not None and len(entries) else None
        self._subscribers = -1
        self.tick = 0
        self.sim_start_s: float | None = None

    def retarget(self, spec: TreeSpec, behaviours: dict[str, py_trees.behaviour.Behaviour],
                 entries: EntryTracker | None = None) -> None:
        """Follow a swapped tree (between ticks): its nodes and entries from the next tick."""
        self._name = spec.name
        self._order = [(n.uid, n.name, n.kind) for n in spec.nodes()]
        self._behaviours = behaviours
        self._entries = entries if entries is not None and len(entries) else None
        self._subscribers = -1  # the next message lists every entry

    def attach(self, tree: py_trees.trees.BehaviourTree) -> TreeStatusPublisher:
        """Add this publisher to ``tree``'s visitors and post-tick handlers; return it."""
        tree.visitors.append(self)
        tree.add_post_tick_handler(self.publish)
        return self

    def initialise(self) -> None:
        """Start a tick: forget the previous tick's visits (py_trees calls this)."""
        self._visited.clear()

    def run(self, behaviour: py_trees.behaviour.Behaviour) -> None:
        """Note a visited behaviour (py_trees calls this for each one ticked)."""
        self._visited.add(id(behaviour))

    def document(self, tree: py_trees.trees.BehaviourTree) -> dict[str, Any]:
        """The status document of the tick that just ended."""
        sim_s = round(self._node.get_clock().now().nanoseconds / 1e9, 3)
        if self.sim_start_s is None:
            self.sim_start_s = sim_s
        nodes = []
        for uid, name, kind in self._order:
            behaviour = self._behaviours.get(uid)
            if behaviour is None:
                continue
            nodes.append([uid, name, kind, behaviour.status.name, behaviour.feedback_message,
                          id(behaviour) in self._visited])
        document = {
            "format": FORMAT, "tree": self._name, "tick": self.tick,
            "sim_s": sim_s, "sim_start_s": self.sim_start_s,
            "status": tree.root.status.name, "complete": bool(self._complete()),
            **self._extra(), "nodes": nodes,
            "blackboard": written_blackboard(self._behaviours),
        }
        if self._entries is not None:
            subscribers = self._publisher.get_subscription_count()
            full = subscribers > self._subscribers  # the first message, or a late joiner
            self._subscribers = subscribers
            document["entries"] = self._entries.changes(full=full)
            document["entries_full"] = full
        return document

    def publish(self, tree: py_trees.trees.BehaviourTree) -> None:
        """Publish the tick's status (a post-tick handler)."""
        self.tick += 1
        message = self._message_type()
        message.data = json.dumps(self.document(tree), separators=(",", ":"))
        self._publisher.publish(message)


class StatusFormatError(ValueError):
    """A message on the status topic is not a status document this version reads."""


def decode_status(text: str) -> dict[str, Any]:
    """Parse one status message's ``data``.

    Args:
        text: The JSON text.

    Returns:
        The document; ``nodes`` entries as dicts with ``uid, name, kind, status, message,
        visited, depth``.

    Raises:
        StatusFormatError: Not JSON, or not format :data:`FORMAT`.
    """
    try:
        document = json.loads(text)
    except ValueError as err:
        raise StatusFormatError(f"not a status document: {err}") from None
    if not isinstance(document, dict) or document.get("format") != FORMAT:
        raise StatusFormatError(f"not a format {FORMAT} status document")
    keys = ("uid", "name", "kind", "status", "message", "visited")
    document["nodes"] = [{**dict(zip(keys, entry, strict=True)), "depth": entry[0].count(".")}
                         for entry in document.get("nodes", [])]
    return document
