"""Seed AMCL with the spawn pose and wait until Nav2 is ACTIVE, before the tree ticks.

AMCL publishes ``map -> odom`` only once it has an initial pose, and the first
``navigate_to_pose`` goal fails unless ``bt_navigator`` is ACTIVE. This runs once at
start-up, so it may block, but always within a wall-clock bound::

    seed_amcl_and_wait_for_nav2(pose=InitialPose(0.0, 0.0, 0.0), timeout_s=30.0,
                                use_sim_time=True, logger=node.get_logger())

With ``nav2_simple_commander`` importable (a real ROS install) it is the course's recipe:
``BasicNavigator.setInitialPose`` + ``waitUntilNav2Active``, run in a helper thread so the
bound holds. ``waitUntilNav2Active`` sleeps 2 s after every ``get_state`` answer, ACTIVE or
not; so first a :class:`~.lifecycle_probe.LifecycleProbe` on the same context asks the
localizer and the navigator itself (no sleeps) until both are ACTIVE: BasicNavigator then
asks each once, on a discovery already done, and its sleeps are paid once (4 s in all).
``waitUntilNav2Active`` waits for each ``get_state`` reply without a bound and
never asks again, and DDS can drop the reply to a request sent just after discovery: when
it is still waiting after :data:`PROBE_AFTER_S` while AMCL has answered the seed, a probe
asks both nodes itself (re-sending) and, once both are ACTIVE, the start-up goes on. A
helper thread left waiting is woken by the context's shutdown and joined at exit.
Otherwise the same steps in plain rclpy on a temporary node and executor:

1. wait until ``/amcl/get_state`` reports ACTIVE (``lifecycle_msgs/srv/GetState``, id 3);
2. publish ``/initialpose`` (PoseWithCovarianceStamped, frame ``map``) every 0.5 s until
   ``/amcl_pose`` answers;
3. wait until ``/bt_navigator/get_state`` reports ACTIVE.

A step that does not finish in time raises :class:`Nav2StartupError` naming it, e.g.
``bt_navigator never reported ACTIVE within 30 s: is Nav2 (or the simulator) running?``.
No ``spin_until_future_complete``: futures are polled in a bounded ``spin_once`` loop.
"""

from __future__ import annotations

import atexit
import math
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from rclpy.context import Context
    from rclpy.executors import Executor
    from rclpy.node import Node

#: ``lifecycle_msgs/msg/State.PRIMARY_STATE_ACTIVE``.
ACTIVE_STATE_ID = 3
_HINT = "is Nav2 (or the simulator) running?"
_SEED_PERIOD_S = 0.5
_STATE_RETRY_S = 0.5
_SPIN_STEP_S = 0.05
#: BasicNavigator sleeps 2 s after each get_state answer: longer than this means a lost reply.
PROBE_AFTER_S = 6.0
#: A get_state request without an answer after this long is sent again.
RESEND_S = 1.0
#: Before BasicNavigator: how often a node not yet ACTIVE (or silent) is asked again.
ASK_FIRST_RESEND_S = 0.25
#: The start-up's steps, in order, as ``on_step`` receives them.
STEPS = ("nav2_discovered", "nav2_active", "amcl_seeded")


class Nav2StartupError(RuntimeError):
    """Nav2 did not come up in time; the message names the step that never completed."""


class StartupInterrupted(Exception):  # noqa: N818 - an interruption, not an error
    """The caller asked to stop (e.g. SIGINT) while waiting for Nav2."""


@dataclass(frozen=True)
class InitialPose:
    """The pose AMCL is seeded with (the robot's spawn pose).

    Attributes:
        x: Metres in ``frame_id``.
        y: Metres in ``frame_id``.
        yaw: Radians about z.
        frame_id: The global frame.
    """

    x: float = 0.0
    y: float = 0.0
    yaw: float = 0.0
    frame_id: str = "map"


def _never() -> bool:
    return False


def _no_step(_step: str) -> None:
    return None


def _nothing() -> None:
    return None


def _log(logger: Any, message: str) -> None:
    if logger is not None:
        logger.info(message)


def basic_navigator_class() -> type | None:
    """Return ``nav2_simple_commander``'s BasicNavigator, or None when not importable."""
    try:
        from nav2_simple_commander.robot_navigator import BasicNavigator
    except ImportError:
        return None
    return BasicNavigator


def seed_amcl_and_wait_for_nav2(
    *,
    pose: InitialPose | None = None,
    timeout_s: float = 30.0,
    use_sim_time: bool = False,
    context: Context | None = None,
    localizer: str = "amcl",
    navigator: str = "bt_navigator",
    should_stop: Callable[[], bool] = _never,
    logger: Any = None,
    prefer_basic_navigator: bool = True,
    ask_first: bool = True,
    on_step: Callable[[str], None] = _no_step,
    meanwhile: Callable[[], None] = _nothing,
    idle: Callable[[float], None] | None = None,
) -> None:
    """Seed AMCL and block (bounded) until the localizer and navigator are ACTIVE.

    Args:
        pose: The seed pose; the origin with yaw 0 by default.
        timeout_s: Wall-clock seconds for all steps together.
        use_sim_time: Stamp the seed with ``/clock`` time (as the rest of the stack).
        context: The rclpy context (the default one when None). BasicNavigator is only
            used on the default context.
        localizer: The localizer's node name (its ``get_state`` is polled).
        navigator: The navigator's node name.
        should_stop: Polled while waiting; True raises :class:`StartupInterrupted`.
        logger: An rclpy logger for progress lines (optional).
        prefer_basic_navigator: Use BasicNavigator when it is importable.
        ask_first: Before BasicNavigator asks, wait (without its sleeps) until both nodes
            answer ACTIVE.
        on_step: Called with each of :data:`STEPS` as it is done (the Nav2 services
            discovered, both nodes ACTIVE, the seed and wait done).
        meanwhile: Called once, in the calling thread, while the wait goes on (with
            BasicNavigator: while it sleeps, both nodes ACTIVE); what it raises ends the
            wait and propagates.
        idle: Called with a step in seconds, instead of a plain sleep, while BasicNavigator
            sleeps after ``meanwhile`` (the caller spins its own node: what ``meanwhile``
            set up keeps its timers and discovery going until the first tick).

    Raises:
        Nav2StartupError: A step did not complete within ``timeout_s``.
        StartupInterrupted: ``should_stop()`` became true.
    """
    pose = pose or InitialPose()
    navigator_cls = basic_navigator_class() if prefer_basic_navigator else None
    if navigator_cls is not None and context is None:
        _with_basic_navigator(navigator_cls, pose=pose, timeout_s=timeout_s,
                              use_sim_time=use_sim_time, localizer=localizer,
                              navigator=navigator, should_stop=should_stop, logger=logger,
                              ask_first=ask_first, on_step=on_step, meanwhile=meanwhile,
                              idle=idle)
    else:
        meanwhile()
        waiter = _Nav2Waiter(pose=pose, timeout_s=timeout_s, use_sim_time=use_sim_time,
                             context=context, should_stop=should_stop, logger=logger)
        waiter.run(localizer, navigator)
        on_step("amcl_seeded")


def _with_basic_navigator(navigator_cls: type, *, pose: InitialPose, timeout_s: float,
                          use_sim_time: bool, localizer: str, navigator: str,
                          should_stop: Callable[[], bool], logger: Any, ask_first: bool,
                          on_step: Callable[[str], None], meanwhile: Callable[[], None],
                          idle: Callable[[float], None] | None = None) -> None:
    """The guide's recipe, with the blocking wait in a thread so the bound holds."""
    from geometry_msgs.msg import PoseStamped
    from rclpy.parameter import Parameter

    from sar_framework.runner.basic_navigator import (
        join_after_shutdown,
        stuck_step,
        wait_quietly,
    )
    from sar_framework.runner.lifecycle_probe import LifecycleProbe

    started = time.monotonic()
    nav = navigator_cls(node_name="sar_nav2_startup")
    nav.set_parameters([Parameter("use_sim_time", Parameter.Type.BOOL, use_sim_time)])
    if ask_first:
        try:
            _wait_until_active(nav, (localizer, navigator), deadline=started + timeout_s,
                               timeout_s=timeout_s, should_stop=should_stop,
                               on_step=on_step, logger=logger)
        except BaseException:
            nav.destroy_node()
            raise
    seed = PoseStamped()
    seed.header.frame_id = pose.frame_id
    seed.header.stamp = nav.get_clock().now().to_msg()
    seed.pose.position.x, seed.pose.position.y = pose.x, pose.y
    seed.pose.orientation.z = math.sin(pose.yaw / 2.0)
    seed.pose.orientation.w = math.cos(pose.yaw / 2.0)
    _log(logger, f"Seeding AMCL at ({pose.x:.2f}, {pose.y:.2f}, yaw {pose.yaw:.2f}) with "
                 "BasicNavigator; waiting for Nav2 to become ACTIVE")
    nav.setInitialPose(seed)
    failure: list[BaseException] = []
    waiter = threading.Thread(target=wait_quietly, daemon=True, name="nav2-startup",
                              args=(nav, navigator, localizer, failure))
    waiter.start()
    asked = time.monotonic()
    probe: LifecycleProbe | None = None
    try:
        meanwhile()
        while waiter.is_alive():
            if should_stop():
                raise StartupInterrupted("stopped while waiting for Nav2")
            now = time.monotonic()
            if now > started + timeout_s:
                raise Nav2StartupError(f"{stuck_step(nav, localizer, navigator)} within "
                                       f"{timeout_s:g} s: {_HINT}")
            if probe is None and now > asked + PROBE_AFTER_S \
                    and getattr(nav, "initial_pose_received", False):
                probe = LifecycleProbe((localizer, navigator), resend_s=RESEND_S,
                                       namespace=nav.get_namespace())
            if probe is not None and probe.all_active():
                _log(logger, "BasicNavigator is still waiting for a get_state reply (DDS "
                             f"dropped one; it does not ask again): {localizer} and "
                             f"{navigator} answered ACTIVE to a fresh request, going on")
                break
            if idle is not None:
                idle(_SPIN_STEP_S)
            else:
                waiter.join(timeout=_SPIN_STEP_S)
    finally:
        if probe is not None:
            probe.close()
        failed = list(failure)  # what the waiter met before we stopped listening
        # Destroyed even while the waiter still waits for a reply DDS dropped: its loop can
        # then only end in InvalidHandle (caught in wait_quietly). Left alive, it asked
        # rclpy for a new global executor after the context's shutdown, which rclpy cannot
        # build any more ("Exception ignored in: Executor.__del__" and a traceback).
        nav.destroy_node()
        if waiter.is_alive():  # inside the global executor's wait until the shutdown
            atexit.register(join_after_shutdown, waiter)
    if failed:
        raise Nav2StartupError(f"BasicNavigator.waitUntilNav2Active failed: {failed[0]}")
    on_step("amcl_seeded")
    _log(logger, "Nav2 is ACTIVE and AMCL has its initial pose")


def _wait_until_active(nav: Any, names: tuple[str, ...], *, deadline: float, timeout_s: float,
                       should_stop: Callable[[], bool], on_step: Callable[[str], None],
                       logger: Any) -> None:
    """Ask ``names`` (re-sending, no sleeps) until every one answers ACTIVE, or raise."""
    from sar_framework.runner.lifecycle_probe import LifecycleProbe

    _log(logger, f"Waiting for {' and '.join(names)} to become ACTIVE before BasicNavigator "
                 "asks (it sleeps 2 s after every answer)")
    probe = LifecycleProbe(names, resend_s=ASK_FIRST_RESEND_S, namespace=nav.get_namespace(),
                           context=nav.context)
    discovered = False
    silent_since: float | None = None  # since when a served node never answered
    try:
        while not probe.all_active():
            if not discovered and all(probe.served(name) for name in names):
                discovered = True
                on_step("nav2_discovered")
            silent = [n for n in names if probe.served(n) and not probe.last_state(n)]
            silent_since = (silent_since or time.monotonic()) if silent else None
            if silent_since is not None and time.monotonic() > silent_since + PROBE_AFTER_S:
                # Asked again and again, never answered: ask on a context of its own, as
                # the fallback below does (new endpoints, a new DDS participant).
                probe.close()
                probe = LifecycleProbe(names, resend_s=RESEND_S, namespace=nav.get_namespace())
                silent_since = None
            if should_stop():
                raise StartupInterrupted("stopped while waiting for Nav2")
            if time.monotonic() > deadline:
                name = probe.not_active()[0]
                service = nav.resolve_service_name(f"{name}/get_state")
                why = (f"{service} never appeared" if not probe.served(name)
                       else f"last state: {probe.last_state(name) or 'no response'}")
                raise Nav2StartupError(f"{name} never reported ACTIVE ({why}) within "
                                       f"{timeout_s:g} s: {_HINT}")
    finally:
        probe.close()
    if not discovered:
        on_step("nav2_discovered")
    on_step("nav2_active")


class _Nav2Waiter:
    """The rclpy equivalent of BasicNavigator's seed-and-wait, on a temporary node."""

    def __init__(self, *, pose: InitialPose, timeout_s: float, use_sim_time: bool,
                 context: Context | None, should_stop: Callable[[], bool], logger: Any) -> None:
        self._pose = pose
        self._timeout_s = timeout_s
        self._use_sim_time = use_sim_time
        self._context = context
        self._should_stop = should_stop
        self._logger = logger
        self._deadline = 0.0
        self._amcl_answered = False

    def run(self, localizer: str, navigator: str) -> None:
        from rclpy.executors import SingleThreadedExecutor
        from rclpy.node import Node
        from rclpy.parameter import Parameter

        node = Node(
            "sar_nav2_startup", context=self._context,
            parameter_overrides=[Parameter("use_sim_time", Parameter.Type.BOOL,
                                           self._use_sim_time)],
        )
        executor = SingleThreadedExecutor(context=self._context)
        executor.add_node(node)
        self._deadline = time.monotonic() + self._timeout_s
        try:
            self._wait_active(node, executor, localizer)
            self._seed(node, executor, localizer)
            self._wait_active(node, executor, navigator)
            _log(self._logger, f"{navigator} is ACTIVE: Nav2 is ready")
        finally:
            executor.remove_node(node)
            executor.shutdown(timeout_sec=0.0)
            node.destroy_node()

    def _spin_until(self, executor: Executor, done: Callable[[], bool], until: float) -> bool:
        """Spin until ``done()``, the step time ``until`` or the overall deadline."""
        while not done():
            if self._should_stop():
                raise StartupInterrupted("stopped while waiting for Nav2")
            now = time.monotonic()
            if now >= min(until, self._deadline):
                return False
            executor.spin_once(timeout_sec=min(_SPIN_STEP_S, max(0.0, until - now)))
        return True

    def _timed_out(self, what: str) -> Nav2StartupError:
        return Nav2StartupError(f"{what} within {self._timeout_s:g} s: {_HINT}")

    def _wait_active(self, node: Node, executor: Executor, name: str) -> None:
        from lifecycle_msgs.srv import GetState

        _log(self._logger, f"Waiting for {name} to become ACTIVE")
        client = node.create_client(GetState, f"{name}/get_state")  # in the robot's namespace
        service = client.service_name
        last_label = ""
        try:
            while True:
                if not self._spin_until(executor, client.service_is_ready, self._deadline):
                    raise self._timed_out(f"{name} never reported ACTIVE ({service} "
                                          "never appeared)")
                futures = [client.call_async(GetState.Request())]

                def answered(futures: list[Any] = futures) -> bool:
                    return any(f.done() for f in futures)

                while not self._spin_until(executor, answered,
                                           time.monotonic() + RESEND_S):
                    if time.monotonic() >= self._deadline:
                        raise self._timed_out(f"{name} never reported ACTIVE (no answer "
                                              f"from {service})")
                    futures.append(client.call_async(GetState.Request()))  # a lost reply
                response = next(f for f in futures if f.done()).result()
                for future in futures:
                    if not future.done():
                        client.remove_pending_request(future)
                state = response.current_state if response else None
                if state is not None and state.id == ACTIVE_STATE_ID:
                    _log(self._logger, f"{name} is ACTIVE")
                    return
                last_label = state.label if state is not None else "no response"
                self._spin_until(executor, _never, time.monotonic() + _STATE_RETRY_S)
                if time.monotonic() >= self._deadline:
                    raise self._timed_out(f"{name} never reported ACTIVE (last state: "
                                          f"{last_label})")
        finally:
            node.destroy_client(client)

    def _seed(self, node: Node, executor: Executor, localizer: str) -> None:
        from geometry_msgs.msg import PoseWithCovarianceStamped

        from sar_framework.ros.qos import latched_qos

        pose = self._pose
        publisher = node.create_publisher(PoseWithCovarianceStamped, "initialpose", 10)
        subscription = node.create_subscription(
            PoseWithCovarianceStamped, "amcl_pose", self._on_amcl_pose, latched_qos())
        _log(self._logger, f"Seeding {localizer}: /initialpose ({pose.x:.2f}, {pose.y:.2f}, "
                           f"yaw {pose.yaw:.2f}) in {pose.frame_id}; waiting for /amcl_pose")
        try:
            while not self._amcl_answered:
                publisher.publish(self._initial_pose_msg(node))
                resend = time.monotonic() + _SEED_PERIOD_S
                self._spin_until(executor, lambda: self._amcl_answered, resend)
                if not self._amcl_answered and time.monotonic() >= self._deadline:
                    raise self._timed_out(f"{localizer} never answered /initialpose on "
                                          "/amcl_pose")
        finally:
            node.destroy_subscription(subscription)
            node.destroy_publisher(publisher)
        _log(self._logger, f"{localizer} answered on /amcl_pose: initial pose accepted")

    def _on_amcl_pose(self, _msg: Any) -> None:
        self._amcl_answered = True

    def _initial_pose_msg(self, node: Node) -> Any:
        from geometry_msgs.msg import PoseWithCovarianceStamped

        pose = self._pose
        msg = PoseWithCovarianceStamped()
        msg.header.frame_id = pose.frame_id
        msg.header.stamp = node.get_clock().now().to_msg()
        msg.pose.pose.position.x, msg.pose.pose.position.y = pose.x, pose.y
        msg.pose.pose.orientation.z = math.sin(pose.yaw / 2.0)
        msg.pose.pose.orientation.w = math.cos(pose.yaw / 2.0)
        # RViz's "2D Pose Estimate" spread: 0.5 m in x and y, ~15 degrees in yaw.
        msg.pose.covariance[0] = msg.pose.covariance[7] = 0.25
        msg.pose.covariance[35] = 0.06853891945200942
        return msg
