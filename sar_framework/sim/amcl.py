"""AMCL stand-in: answers each ``/initialpose`` on ``/amcl_pose`` and reports ACTIVE.

The simulator knows the robot's true pose, so localisation is perfect: the seed only
switches localisation on (``map -> odom`` is published from then on, unless the simulator
starts localised). The answer echoes the seed, as AMCL's first estimate does; a seed far
from the truth is logged as a warning but does not move the robot or the estimate.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from geometry_msgs.msg import PoseWithCovarianceStamped
from rclpy.node import Node

from sar_framework.ros.qos import latched_qos  # /amcl_pose: depth 1, as Nav2's AMCL
from sar_framework.sim.lifecycle import serve_active_state
from sar_framework.sim.messages import pose_to_2d, time_msg
from sar_framework.sim.world import Pose2D

SEED_WARN_DISTANCE_M = 0.5
"""A seed farther than this from the true pose is logged as a warning."""

# AMCL's default initial covariance: 0.5 m standard deviation in x and y, pi/12 rad in yaw.
_DEFAULT_COVARIANCE = {0: 0.25, 7: 0.25, 35: (math.pi / 12.0) ** 2}


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
        self.node = Node("amcl")
        self._truth = truth
        self._now_ns = now_ns
        self._global_frame = global_frame
        self._localized = localized
        self.seeds = 0
        serve_active_state(self.node)
        self._publisher = self.node.create_publisher(
            PoseWithCovarianceStamped, "/amcl_pose", latched_qos()
        )
        self.node.create_subscription(
            PoseWithCovarianceStamped, "/initialpose", self._on_initial_pose, 10
        )

    @property
    def localized(self) -> bool:
        """Whether ``map -> odom`` is known (seeded, or localised from the start)."""
        return self._localized

    def _on_initial_pose(self, msg: PoseWithCovarianceStamped) -> None:
        log = self.node.get_logger()
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
        answer = PoseWithCovarianceStamped()
        answer.header.frame_id = self._global_frame
        answer.header.stamp = time_msg(self._now_ns())
        answer.pose.pose = msg.pose.pose
        if any(msg.pose.covariance):
            answer.pose.covariance = msg.pose.covariance
        else:
            for index, variance in _DEFAULT_COVARIANCE.items():
                answer.pose.covariance[index] = variance
        self._localized = True
        self.seeds += 1
        self._publisher.publish(answer)
        log.info(
            f"Initial pose received: ({seed.x:.2f}, {seed.y:.2f}, yaw {seed.yaw:.2f}); "
            "published /amcl_pose."
        )
