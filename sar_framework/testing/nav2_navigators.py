"""Nav2's navigator trees run against the embedded simulator: import, reset, run, observe.

The trees are read where ROS installs them (``share/nav2_bt_navigator/behavior_trees``
under ``$AMENT_PREFIX_PATH``) or from the ROS overlay's sources, never copied; they are
imported with our BT.CPP importer (``sar-tree import --nodes-model nav2_tree_nodes.xml``)
and ticked in-process on a ROS node that declares the BT navigator's parameters as
``bt_navigator`` does (:data:`NAVIGATOR_PARAMETERS`, from config/nav2_params.yaml)::

    with ros_node("bt_navigator") as (node, executor):
        declare_navigator_parameters(node)
        bench = NavigatorBench(node, executor)
        bench.reset(phantom_obstacles=["1.0:-0.5:0.3"])   # faults, then /sar_sim/reset
        run = bench.run(import_navigator(xml, tmp), {"goal": pose(1.0, -0.5)})
        assert run.status == Status.SUCCESS and "ClearLocalCostmap-Subtree" in run.succeeded()

A run is observed as the runner observes a mission: the runner's own
:class:`~sar_framework.runner.status_file.StatusFileWriter` watches the ticks, so
:attr:`NavigatorRun.events` are the leaf verdicts of the ``status`` events and
:attr:`NavigatorRun.reasons` the reason records (failure, cancel, retry...) the runner
would log and put in mission.json.
"""

from __future__ import annotations

import math
import os
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import py_trees
from py_trees.blackboard import Blackboard
from py_trees.common import Status

from sar_framework.events.emitter import SETUP_KEY, EventEmitter
from sar_framework.testing.sim_control import reset_sim, set_sim_params
from sar_framework.testing.spin import spin_until

#: Where the ROS 2 sources are, as tools/bootstrap.py finds them: ``SAR_ROS_OVERLAY_SRC``, else
#: ``shared/ros-overlay/src`` beside the repository.
OVERLAY = Path(os.environ.get("SAR_ROS_OVERLAY_SRC")
               or Path(__file__).resolve().parents[2].parent / "shared" / "ros-overlay" / "src")
#: bt_navigator's parameters the leaves read, as config/nav2_params.yaml sets them
#: (``default_server_timeout`` raised from 20 ms: a loaded machine acknowledges slower).
NAVIGATOR_PARAMETERS: dict[str, Any] = {
    "global_frame": "map",
    "robot_base_frame": "base_link",
    "odom_topic": "/odometry/filtered",
    "bt_loop_duration": 10,
    "default_server_timeout": 2000,
    "wait_for_service_timeout": 1000,
    "action_server_result_timeout": 900.0,
    "goal_reached_tol": 0.25,
    "use_sim_time": True,
}
_TERMINAL = (Status.SUCCESS, Status.FAILURE)


def nav2_share(package: str, relative: str) -> Path:
    """``share/<package>/<relative>`` of the ROS install, else the overlay's source.

    Args:
        package: The ROS package.
        relative: The path inside its share directory.
    """
    for prefix in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep):
        found = Path(prefix) / "share" / package / relative
        if prefix and found.exists():
            return found
    return OVERLAY / package / relative


def navigator_trees() -> dict[str, Path]:
    """Nav2's navigator tree files by stem (twelve in Jazzy)."""
    folder = nav2_share("nav2_bt_navigator", "behavior_trees")
    return {path.stem: path for path in sorted(folder.glob("*.xml"))}


def import_navigator(xml: Path, folder: Path) -> Path:
    """Import a navigator tree with Nav2's palette; return the tree file written.

    Args:
        xml: The BT.CPP XML file.
        folder: Where the tree file (``<stem>.yaml``) is written.

    Raises:
        AssertionError: The importer refused the file (its diagnostics are in the message).
    """
    import contextlib
    import io

    from sar_framework.cli import main

    palette = nav2_share("nav2_behavior_tree", "nav2_tree_nodes.xml")
    tree = folder / f"{xml.stem}.yaml"
    errors = io.StringIO()
    with contextlib.redirect_stderr(errors):
        code = main(["import", str(xml), "--nodes-model", str(palette), "-o", str(tree)])
    assert code == 0, errors.getvalue()
    return tree


def declare_navigator_parameters(node: Any, overrides: Mapping[str, Any] | None = None) -> None:
    """Declare bt_navigator's parameters on ``node`` (:data:`NAVIGATOR_PARAMETERS`).

    Args:
        node: The rclpy node the tree is set up with.
        overrides: Values replacing the defaults.
    """
    from rclpy.parameter import Parameter

    for name, value in {**NAVIGATOR_PARAMETERS, **(overrides or {})}.items():
        if node.has_parameter(name):  # use_sim_time: every rclpy node has it
            node.set_parameters([Parameter(name, value=value)])
        else:
            node.declare_parameter(name, value)


@dataclass
class NavigatorRun:
    """What one run of a navigator tree did.

    Attributes:
        status: The root's final status (RUNNING when the run timed out).
        events: The leaf verdicts (``status`` events) as the runner records them: dicts
            with ``uid``, ``name``, ``kind``, ``status``, ``message``.
        reasons: The runner's reason records (``what``: failure, cancel, retry, ...).
        blackboard: The root blackboard after the run (``/name -> value``).
        ticks: Ticks made.
        wall_s: Wall seconds the run took.
        pose: The robot's (x, y) from TF after the run, or None.
    """

    status: Status
    events: list[dict[str, Any]] = field(default_factory=list)
    reasons: list[dict[str, Any]] = field(default_factory=list)
    blackboard: dict[str, Any] = field(default_factory=dict)
    ticks: int = 0
    wall_s: float = 0.0
    pose: tuple[float, float] | None = None

    def ended(self, status: str) -> list[str]:
        """The names of the leaves that ended with ``status``, in order (repeats kept)."""
        return [e["name"] for e in self.events if e["status"] == status]

    def succeeded(self) -> list[str]:
        """The names of the leaves that ended SUCCESS, in order."""
        return self.ended("SUCCESS")

    def failed(self) -> list[str]:
        """The names of the leaves that ended FAILURE, in order."""
        return self.ended("FAILURE")

    def summary(self) -> str:
        """A few lines for an assertion message."""
        lines = [f"{self.status.name} after {self.ticks} ticks, {self.wall_s:.2f} s, "
                 f"pose {self.pose}"]
        lines += [f"  {e['status']:7} {e['name']}: {e['message']}" for e in self.events]
        lines += [f"  reason {r['what']}: {r['name']}: {r['message']}" for r in self.reasons]
        return "\n".join(lines)


def goal_pose(x: float, y: float, yaw: float = 0.0) -> Any:
    """A ``geometry_msgs/PoseStamped`` in ``map`` at (x, y), heading ``yaw`` (rad)."""
    from geometry_msgs.msg import PoseStamped

    msg = PoseStamped()
    msg.header.frame_id = "map"
    msg.pose.position.x, msg.pose.position.y = x, y
    msg.pose.orientation.z, msg.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    return msg


class NavigatorBench:
    """Runs navigator trees one after another against one running simulator.

    Args:
        node: The test's ROS node (bt_navigator's parameters declared on it).
        executor: The executor spinning ``node``.
    """

    def __init__(self, node: Any, executor: Any) -> None:
        from sar_plugins.nav2.robot_context import ROBOT_POSE_KEY

        from sar_framework.ros.robot_state import robot_context

        self.node = node
        self.executor = executor
        self.context = robot_context(node)
        self.pose = self.context[ROBOT_POSE_KEY]
        self.pose.start()
        self._warm_up()

    def _warm_up(self) -> None:
        """Tick a GoalReached until the leaves' shared TF buffer has the robot's pose.

        bt_navigator's TF buffer lives as long as the navigator, so it holds the robot's
        pose long before the first goal; the leaves' buffer is made at their first setup.
        """
        from sar_framework.testing.trees import tree_from_yaml

        loaded = tree_from_yaml("format: 1\nroot:\n  GoalReached: {goal: '{goal}'}\n"
                                "blackboard:\n  goal: {type: geometry_msgs/msg/PoseStamped}\n"
                                ).loaded
        Blackboard.storage["/goal"] = goal_pose(0.0, 0.0)
        tree = py_trees.trees.BehaviourTree(loaded.root)
        tree.setup(timeout=5.0, node=self.node)
        try:
            assert spin_until(self.executor, lambda: "pose not available" not in str(
                loaded.root.feedback_message), 10.0, step=tree.tick), "no robot pose in TF"
        finally:
            tree.shutdown()

    def set_sim(self, **params: Any) -> None:
        """Set parameters of ``/sar_sim`` (rclpy SetParameters); each must be accepted.

        Args:
            **params: name -> value (a list of str for ``phantom_obstacles``...).
        """
        results = set_sim_params(self.node, self.executor, **params)
        refused = [f"{name}: {result.reason}" for name, result in
                   zip(params, results, strict=True) if not result.successful]
        assert not refused, f"/sar_sim refused {refused}"

    def reset(self, **faults: Any) -> None:
        """Set ``faults`` (sim parameters), then ``/sar_sim/reset``: the robot back at spawn.

        Args:
            **faults: Simulator parameters to set before the reset.
        """
        if faults:
            self.set_sim(**faults)
        answer = reset_sim(self.node, self.executor)
        assert answer.success, f"/sar_sim/reset: {answer.message}"
        self.wait_until_at(0.0, 0.0)

    def where(self) -> tuple[float, float] | None:
        """The robot's (x, y) in ``map`` from TF, or None."""
        return self.pose("", "")

    def _tf_stamp_ns(self) -> int:
        """The stamp of TF's latest ``map -> base_link`` (0 without one)."""
        from rclpy.time import Time

        try:
            found = self.pose.buffer.lookup_transform("map", "base_link", Time())
        except Exception:  # tf2's lookup and extrapolation errors
            return 0
        return Time.from_msg(found.header.stamp).nanoseconds

    def settled_pose(self, after_ns: int, still_s: float = 2.0,
                     timeout: float = 30.0) -> tuple[float, float] | None:
        """The robot's pose once TF shows it at rest for ``still_s`` simulated seconds.

        TF and ``/clock`` may both lag the simulator on a loaded machine, so a TF stamp at
        the run's end is not enough: the pose is read once two transforms ``still_s``
        apart (both after ``after_ns``) agree within a centimetre.

        Args:
            after_ns: The run's end on the ROS clock: older transforms do not count.
            still_s: Simulated seconds the robot must stay put.
            timeout: Wall seconds: an outer safety bound.

        Raises:
            AssertionError: TF never showed the robot at rest after the run (the pose
                before the run would otherwise pass for the pose after it).
        """
        first: tuple[int, tuple[float, float] | None] | None = None

        def at_rest() -> bool:
            nonlocal first
            stamp = self._tf_stamp_ns()
            if stamp < after_ns:
                return False
            now = (stamp, self.where())
            if first is None or first[1] is None or now[1] is None \
                    or math.dist(first[1], now[1]) > 0.01:
                first = now
                return False
            return stamp - first[0] >= still_s * 1e9

        assert spin_until(self.executor, at_rest, timeout), (
            f"TF never showed the robot at rest for {still_s} s after the run within "
            f"{timeout} s (outer safety bound); last pose {self.where()}, stamped "
            f"{self._tf_stamp_ns()} ns, the run ended at {after_ns} ns")
        return self.where()

    def wait_until_at(self, x: float, y: float, tolerance: float = 0.05,
                      timeout: float = 10.0) -> None:
        """Spin until TF puts the robot within ``tolerance`` of (x, y).

        Raises:
            AssertionError: Not there within ``timeout`` wall seconds.
        """
        def there() -> bool:
            found = self.where()
            return found is not None and abs(found[0] - x) + abs(found[1] - y) <= tolerance

        assert spin_until(self.executor, there, timeout), f"robot at {self.where()}"

    def run(self, tree_file: Path, blackboard: Mapping[str, Any], timeout: float = 30.0,
            until: Callable[[], bool] | None = None) -> NavigatorRun:
        """Load, set up and tick a tree until it ends (or ``timeout`` wall seconds pass).

        Args:
            tree_file: The imported tree file.
            blackboard: Root blackboard entries set before the first tick (``goal``...).
            timeout: Wall seconds.
            until: Also stop (halting the tree) once this is true, for a tree that never
                ends by itself (follow_point keeps following).

        Returns:
            The run; its tree is shut down (goals still running are cancelled).
        """
        from sar_framework.engine.api import load_tree
        from sar_framework.runner.status_file import StatusFileWriter

        Blackboard.storage.clear()
        loaded = load_tree(tree_file, self.context)
        for name, value in blackboard.items():
            Blackboard.storage[f"/{name}"] = value
        clock = self.node.get_clock()
        started = time.monotonic()
        kinds = {n.uid: n.kind for n in loaded.spec.nodes()}
        emitter = EventEmitter(nodes={u: (b, kinds[u]) for u, b in loaded.behaviours.items()})
        writer = StatusFileWriter(str(tree_file), loaded.spec, loaded.behaviours,
                                  lambda: clock.now().nanoseconds / 1e9, completion="once",
                                  emitter=emitter, wall_start=started)
        tree = py_trees.trees.BehaviourTree(loaded.root)
        tree.setup(timeout=5.0, node=self.node, **{SETUP_KEY: emitter})
        tree.visitors.append(writer)
        try:
            spin_until(self.executor, lambda: tree.root.status in _TERMINAL
                       or (until is not None and until()), timeout,
                       step=lambda: tree.tick(post_tick_handler=writer.after_tick))
        finally:
            status = tree.root.status
            if status == Status.RUNNING:
                tree.root.stop(Status.INVALID)  # a halt: running goals are cancelled
            tree.shutdown()
        return NavigatorRun(status=status, events=list(writer.events),
                            reasons=list(writer.failures),
                            blackboard={k: v for k, v in Blackboard.storage.items()},
                            ticks=writer.ticks, wall_s=time.monotonic() - started,
                            pose=self.settled_pose(clock.now().nanoseconds))
