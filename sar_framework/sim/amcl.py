"""AMCL stand-in: a lifecycle ``amcl`` node publishing ``/amcl_pose`` as Nav2's AMCL does.

The simulator knows the robot's true pose, so localisation is perfect. While ACTIVE:

- ``/initialpose`` seeds it (from then on ``map -> odom`` is published, unless the simulator
  starts localised) and is answered at once on ``/amcl_pose`` with the seed, as AMCL's first
  estimate; a seed far from the truth is logged as a warning but does not move the robot;
- as the robot moves, a filter update happens when it has travelled ``update_min_d`` metres
  or turned ``update_min_a`` radians since the last one (checked at the laser rate, 10 Hz of
  simulated time), and each update publishes the true pose on ``/amcl_pose`` with a converged
  filter's covariance.

``/amcl_pose`` is RELIABLE, TRANSIENT_LOCAL, depth 1, as AMCL's. An inactive AMCL ignores
``/initialpose`` ("Received initial pose request, but AMCL is not yet in the active state")
and the robot counts as not localised.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from geometry_msgs.msg import Pose, PoseWithCovarianceStamped

from sar_framework.ros.qos import latched_qos
from sar_framework.sim.lifecycle import Nav2LifecycleNode
from sar_framework.sim.messages import pose_msg, pose_to_2d, time_msg
from sar_framework.sim.world import Pose2D

SEED_WARN_DISTANCE_M = 0.5
"""A seed farther than this from the true pose is logged as a warning."""
LASER_PERIOD_NS = 100_000_000
"""Simulated nanoseconds between two filter-update checks (a 10 Hz laser)."""

# AMCL's default initial covariance: 0.5 m standard deviation in x and y, pi/12 rad in yaw.
_DEFAULT_COVARIANCE = {0: 0.25, 7: 0.25, 35: (math.pi / 12.0) ** 2}
# A converged particle cloud: about 5 cm in x and y, 3 degrees in yaw.
_TRACKING_COVARIANCE = {0: 0.0025, 7: 0.0025, 35: math.radians(3.0) ** 2}


class AmclStandIn:
    """The ``amcl`` node of the simulator.

    Args:
        truth: Returns the robot's true map pose.
        now_ns: Returns the simulated time, nanoseconds.
        global_frame: The map frame name.
        localized: Whether to count as localised before any seed.
    """

    def __init__(
        self,
        truth: Callable[[], Pose2D],
        now_ns: Callable[[], int],
        *,
        global_frame: str = "map",
        localized: bool = True,
    ) -> None:
        self.node = Nav2LifecycleNode("amcl")
        self._truth = truth
        self._now_ns = now_ns
        self._global_frame = global_frame
        self._seeded = localized
        self.seeds = 0
        self.updates = 0
        self._last_update: Pose2D | None = None
        self._next_check_ns = 0
        self.node.declare_parameter("update_min_d", 0.25)
        self.node.declare_parameter("update_min_a", 0.2)
        self._publisher = self.node.create_publisher(
            PoseWithCovarianceStamped, "amcl_pose", latched_qos()
        )
        self.node.create_subscription(
            PoseWithCovarianceStamped, "initialpose", self._on_initial_pose, 10
        )

    @property
    def localized(self) -> bool:
        """Whether ``map -> odom`` is known: ACTIVE and seeded (or localised from the start)."""
        return self._seeded and self.node.active

    def on_motion(self, now_ns: int) -> None:
        """Called by the physics loop: run a filter update when the robot has moved enough."""
        if now_ns < self._next_check_ns or not self.localized:
            return
        self._next_check_ns = now_ns + LASER_PERIOD_NS
        pose = self._truth()
        last = self._last_update
        if last is not None:
            moved = math.hypot(pose.x - last.x, pose.y - last.y)
            turned = abs(math.remainder(pose.yaw - last.yaw, math.tau))
            if moved < self.node.get_parameter("update_min_d").value and \
                    turned < self.node.get_parameter("update_min_a").value:
                return
        self._last_update = pose
        self.updates += 1
        self._publish(pose_msg(pose), _TRACKING_COVARIANCE, now_ns)

    def reset(self, *, localized: bool) -> None:
        """Forget the filter's state, as at start-up (``~/reset`` of the simulator)."""
        self._seeded = localized
        self._last_update = None
        self._next_check_ns = 0

    def publish_truth(self, now_ns: int) -> None:
        """Publish the true pose on ``/amcl_pose`` now, if localised."""
        if self.localized:
            pose = self._truth()
            self._last_update = pose
            self._publish(pose_msg(pose), _TRACKING_COVARIANCE, now_ns)

    def _publish(self, pose: Pose, covariance: dict[int, float] | list[float],
                 stamp_ns: int) -> None:
        answer = PoseWithCovarianceStamped()
        answer.header.frame_id = self._global_frame
        answer.header.stamp = time_msg(stamp_ns)
        answer.pose.pose = pose
        if isinstance(covariance, dict):
            for index, variance in covariance.items():
                answer.pose.covariance[index] = variance
        else:
            answer.pose.covariance = covariance
        self._publisher.publish(answer)

    def _on_initial_pose(self, msg: PoseWithCovarianceStamped) -> None:
        log = self.node.get_logger()
        if not self.node.active:
            log.warning("Received initial pose request, but AMCL is not yet in the active state")
            return
        frame = msg.header.frame_id.lstrip("/")
        if not frame:
            log.warning("Received initial pose with empty frame_id; assuming the global frame.")
        elif frame != self._global_frame:
            log.warning(
                f"Ignoring initial pose in frame {msg.header.frame_id!r}; initial poses must be "
                f"in the global frame {self._global_frame!r}."
            )
            return
        seed = pose_to_2d(msg.pose.pose)
        truth = self._truth()
        error = math.hypot(seed.x - truth.x, seed.y - truth.y)
        if error > SEED_WARN_DISTANCE_M:
            log.warning(
                f"Initial pose ({seed.x:.2f}, {seed.y:.2f}) is {error:.2f} m from the simulated "
                f"robot ({truth.x:.2f}, {truth.y:.2f}); localisation stays on the true pose."
            )
        covariance = msg.pose.covariance if any(msg.pose.covariance) else _DEFAULT_COVARIANCE
        self._seeded = True
        self.seeds += 1
        self._last_update = truth
        self._publish(msg.pose.pose, covariance, self._now_ns())
        log.info(
            f"Initial pose received: ({seed.x:.2f}, {seed.y:.2f}, yaw {seed.yaw:.2f}); "
            "published /amcl_pose."
        )
