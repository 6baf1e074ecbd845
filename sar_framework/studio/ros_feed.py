"""The live studio's ROS side: a node that feeds a running mission into a session.

:class:`LiveFeed` spins its own rclpy node (``sar_studio``) in a thread and subscribes to
what the mission publishes on the same ROS domain:

- ``/sar_tree/status`` (:mod:`sar_framework.runner.tree_status`): the tree's statuses,
  blackboard and entries, every tick;
- ``/sar_mission/events`` (:mod:`sar_framework.runner.event_topic`): the typed events
  (reasons, goals, an app's events, completion);
- ``/tf`` and ``/tf_static``: the robot's pose in ``map``
  (:class:`~sar_framework.recording.readback.PoseTracker`, as replay reads them);
- ``/map``: the occupancy grid the map server latches (injected obstacles included).

It is also the studio's client of the runner's hot reload service
(``/sar_mission_runner/reload``, ``std_srvs/srv/Trigger``, :mod:`sar_framework.runner.reload`):
:meth:`LiveFeed.reload` asks it and returns its answer, and :meth:`LiveFeed.ticked_tree`
reads which tree file the runner ticks (its parameter ``tree``): the session learns it from
the first status when the studio was not given it (:attr:`~.session.Session.learn_tree`).
A ``tree_swapped`` event makes the session draw the tree again from its file
(:meth:`~.session.Session.redraw_from_file`).

All are latched or kept by their publishers, so a studio started after the mission sees
its recent past. A status with a lower tick than the last one is a new mission: the
session starts over. When the mission ends nothing more arrives, and the last frame stays.

This is the only studio module that imports ROS.
"""

from __future__ import annotations

import threading
import time
from typing import Any

from sar_framework.events.event import EVENT_TOPIC, EventKind
from sar_framework.runner.tree_status import STATUS_HISTORY, STATUS_TOPIC, decode_status
from sar_framework.studio.reload import ReloadUnavailableError
from sar_framework.studio.session import Session
from sar_framework.studio.timeline import Timeline
from sar_framework.studio.world_view import grid_view

#: Seconds between spins of the feed's executor (how soon it notices a stop).
SPIN_S = 0.1
#: A pose is kept when the robot moved this far (m) or turned this much (rad)...
POSE_STEP = (0.01, 0.02)
#: ...or this much (simulated) time passed since the last kept one (s).
POSE_PERIOD_S = 0.5
NODE_NAME = "sar_studio"
#: The runner's hot reload service (its node ``sar_mission_runner``, service ``~/reload``).
RELOAD_SERVICE = "/sar_mission_runner/reload"
#: The runner's parameter service: its ``tree`` says which file it ticks.
PARAMETERS_SERVICE = "/sar_mission_runner/get_parameters"
#: How long :meth:`LiveFeed.reload` waits for the service to appear (wall seconds).
SERVICE_WAIT_S = 5.0
#: How long it waits for the answer: the runner validates, builds and sets up the tree first.
ANSWER_WAIT_S = 60.0


class LiveFeed:
    """Feeds the mission on this ROS domain into ``session`` until :meth:`stop`.

    Args:
        session: The live session to fill.
    """

    def __init__(self, session: Session) -> None:
        self._session = session
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="sar-studio-ros", daemon=True)
        self._tracker: Any = None
        self._last_pose: tuple[float, float, float, float] | None = None
        self._reload_client: Any = None
        self._parameters_client: Any = None
        self._learning = False
        self._ready = threading.Event()
        self.error: str | None = None

    def start(self) -> LiveFeed:
        """Start spinning in the feed's thread; return self."""
        self._thread.start()
        return self

    def stop(self) -> None:
        """Stop spinning and shut the node down (waits for the thread)."""
        self._stop.set()
        self._thread.join(timeout=5.0)

    def reload(self) -> tuple[bool, str]:
        """Ask the runner to reload its tree file (any thread but the feed's).

        Returns:
            The service's answer: whether the tree was swapped, and its message (the swap's
            summary, or why it was refused: every diagnostic of an invalid file).

        Raises:
            ReloadUnavailableError: The feed is not running, no runner offers the service on this
                domain, or it did not answer in time.
        """
        import time as clock

        from std_srvs.srv import Trigger

        if not self._ready.wait(SERVICE_WAIT_S) or self._reload_client is None:
            raise ReloadUnavailableError(f"the studio's ROS feed is not running ({self.error})")
        client = self._reload_client
        if not client.wait_for_service(timeout_sec=SERVICE_WAIT_S):
            raise ReloadUnavailableError(f"no mission offers {RELOAD_SERVICE} on this ROS domain "
                                    "(is its runner running?)")
        future = client.call_async(Trigger.Request())
        deadline = clock.monotonic() + ANSWER_WAIT_S
        while not future.done():  # the feed's executor, in its thread, takes the answer
            if clock.monotonic() > deadline:
                future.cancel()
                raise ReloadUnavailableError(f"{RELOAD_SERVICE} did not answer within "
                                        f"{ANSWER_WAIT_S:g} s")
            clock.sleep(0.02)
        answer = future.result()
        return bool(answer.success), str(answer.message)

    def ticked_tree(self) -> str | None:
        """The tree file the mission's runner ticks: its parameter ``tree``, as it was given.

        Returns:
            The path, or None when no runner answers (the reload then says why).
        """
        import time as clock

        from rcl_interfaces.msg import ParameterType
        from rcl_interfaces.srv import GetParameters

        client = self._parameters_client
        if not self._ready.wait(SERVICE_WAIT_S) or client is None \
                or not client.wait_for_service(timeout_sec=SERVICE_WAIT_S):
            return None
        future = client.call_async(GetParameters.Request(names=["tree"]))
        deadline = clock.monotonic() + SERVICE_WAIT_S
        while not future.done():
            if clock.monotonic() > deadline:
                future.cancel()
                return None
            clock.sleep(0.02)
        values = future.result().values
        if not values or values[0].type != ParameterType.PARAMETER_STRING:
            return None
        return str(values[0].string_value)

    # -- the thread --------------------------------------------------------------------------
    def _run(self) -> None:
        import rclpy
        from nav_msgs.msg import OccupancyGrid
        from rcl_interfaces.srv import GetParameters
        from rclpy.executors import SingleThreadedExecutor
        from rclpy.node import Node
        from rclpy.signals import SignalHandlerOptions
        from sar_interfaces.msg import MissionEvent as EventMsg
        from std_msgs.msg import String
        from std_srvs.srv import Trigger
        from tf2_msgs.msg import TFMessage

        from sar_framework.recording.readback import PoseTracker
        from sar_framework.ros.qos import latched_qos, tf_static_qos
        from sar_framework.runner.event_topic import event_qos

        self._tracker = PoseTracker()
        context = rclpy.Context()
        rclpy.init(context=context, signal_handler_options=SignalHandlerOptions.NO)
        node = Node(NODE_NAME, context=context)
        node.create_subscription(String, STATUS_TOPIC, self._on_status,
                                 latched_qos(STATUS_HISTORY))
        node.create_subscription(EventMsg, EVENT_TOPIC, self._on_event, event_qos())
        node.create_subscription(TFMessage, "/tf", self._on_tf, 100)
        node.create_subscription(TFMessage, "/tf_static", self._on_tf, tf_static_qos())
        node.create_subscription(OccupancyGrid, "/map", self._on_map, latched_qos())
        self._reload_client = node.create_client(Trigger, RELOAD_SERVICE)
        self._parameters_client = node.create_client(GetParameters, PARAMETERS_SERVICE)
        self._ready.set()
        executor = SingleThreadedExecutor(context=context)
        executor.add_node(node)
        try:
            while not self._stop.is_set() and context.ok():
                executor.spin_once(timeout_sec=SPIN_S)
        except Exception as err:  # the page says so; the server keeps serving
            self.error = f"{type(err).__name__}: {err}"
            node.get_logger().error(f"the studio's ROS feed stopped: {self.error}")
        finally:
            self._reload_client = self._parameters_client = None
            executor.shutdown(timeout_sec=0.0)
            node.destroy_node()
            rclpy.try_shutdown(context=context)

    def _on_status(self, message: Any) -> None:
        try:
            document = decode_status(message.data)
        except ValueError:
            return
        session = self._session
        with session.lock:
            statuses = session.timeline.statuses
            if statuses and document.get("tick", 0) == statuses[-1].get("tick"):
                return  # the same tick again (a latched copy)
            if statuses and document.get("tick", 0) < statuses[-1].get("tick", 0):
                session.timeline = Timeline()  # a new mission
                self._last_pose = None
            session.adopt_status_tree(document)
            session.timeline.add_status(document, time.monotonic())
        session.changed()
        if session.learn_tree is not None and session.editor is None and not self._learning:
            self._learning = True  # asked aside: the answer comes through this thread
            threading.Thread(target=self._learn_tree, name="sar-studio-tree",
                             daemon=True).start()

    def _learn_tree(self) -> None:
        """Tell the session which tree file the runner ticks (again later if it does not say)."""
        ticked = self.ticked_tree()
        if ticked is not None and self._session.learn_tree is not None:
            self._session.learn_tree(ticked)
        self._learning = self._session.editor is not None

    def _on_event(self, message: Any) -> None:
        from sar_framework.runner.event_topic import from_message

        try:
            event = from_message(message)
        except ValueError:
            return  # a kind a later version added
        with self._session.lock:
            self._session.timeline.add_event(event)
        self._session.changed()
        if event.kind == EventKind.TREE_SWAPPED:  # drawn aside: Graphviz takes a while
            threading.Thread(target=self._session.redraw_from_file, name="sar-studio-redraw",
                             daemon=True).start()

    def _on_tf(self, message: Any) -> None:
        kept = []
        for pose in self._tracker.update(message):
            last = self._last_pose
            if last is None or abs(pose[1] - last[1]) + abs(pose[2] - last[2]) >= POSE_STEP[0] \
                    or abs(pose[3] - last[3]) >= POSE_STEP[1] or pose[0] - last[0] >= POSE_PERIOD_S:
                kept.append(pose)
                self._last_pose = pose
        if not kept:
            return
        with self._session.lock:
            for pose in kept:
                self._session.timeline.add_pose(*pose)
        self._session.changed()

    def _on_map(self, message: Any) -> None:
        info = message.info
        grid = grid_view(info.width, info.height, info.resolution,
                         (info.origin.position.x, info.origin.position.y), message.data)
        with self._session.lock:
            self._session.world = {**self._session.world, "grid": grid}
        self._session.changed()
