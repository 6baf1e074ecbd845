"""ROS message builders and conversions for the simulator (poses, stamps, TF, odom, map).

Imports ROS message packages at module level: import this module only in ROS code.
"""

from __future__ import annotations

import math

from builtin_interfaces.msg import Duration, Time
from geometry_msgs.msg import Pose, PoseStamped, Quaternion, TransformStamped
from nav_msgs.msg import OccupancyGrid as OccupancyGridMsg
from nav_msgs.msg import Odometry
from tf2_msgs.msg import TFMessage

from sar_framework.sim.clock import NS_PER_S, split_ns
from sar_framework.sim.occupancy import OccupancyGrid
from sar_framework.sim.world import Pose2D


def time_msg(stamp_ns: int) -> Time:
    """Return ``builtin_interfaces/Time`` for simulated nanoseconds."""
    sec, nanosec = split_ns(stamp_ns)
    return Time(sec=sec, nanosec=nanosec)


def duration_msg(seconds: float) -> Duration:
    """Return ``builtin_interfaces/Duration`` for non-negative seconds."""
    sec, nanosec = split_ns(max(round(seconds * NS_PER_S), 0))
    return Duration(sec=sec, nanosec=nanosec)


def yaw_to_quaternion(yaw: float) -> Quaternion:
    """Return the quaternion of a rotation by ``yaw`` radians about z."""
    return Quaternion(x=0.0, y=0.0, z=math.sin(yaw / 2.0), w=math.cos(yaw / 2.0))


def quaternion_to_yaw(q: Quaternion) -> float:
    """Return the heading (rotation about z) of a quaternion, radians.

    An all-zero quaternion (an unset orientation) gives 0.
    """
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def pose_to_2d(pose: Pose) -> Pose2D:
    """Return the planar part of a ``geometry_msgs/Pose``."""
    return Pose2D(pose.position.x, pose.position.y, quaternion_to_yaw(pose.orientation))


def pose_msg(pose: Pose2D) -> Pose:
    """Return a ``geometry_msgs/Pose`` on the ground plane."""
    msg = Pose()
    msg.position.x, msg.position.y = float(pose.x), float(pose.y)
    msg.orientation = yaw_to_quaternion(pose.yaw)
    return msg


def pose_stamped(pose: Pose2D, frame_id: str, stamp_ns: int) -> PoseStamped:
    """Return a ``geometry_msgs/PoseStamped``."""
    msg = PoseStamped()
    msg.header.frame_id = frame_id
    msg.header.stamp = time_msg(stamp_ns)
    msg.pose = pose_msg(pose)
    return msg


def relative_pose(origin: Pose2D, pose: Pose2D) -> Pose2D:
    """Express ``pose`` (a map pose) in the frame whose map pose is ``origin``."""
    c, s = math.cos(origin.yaw), math.sin(origin.yaw)
    dx, dy = pose.x - origin.x, pose.y - origin.y
    yaw = math.remainder(pose.yaw - origin.yaw, math.tau)
    return Pose2D(c * dx + s * dy, -s * dx + c * dy, yaw)


def transform(parent: str, child: str, pose: Pose2D, stamp_ns: int) -> TransformStamped:
    """Return the transform ``parent -> child`` where ``child`` sits at ``pose`` in ``parent``."""
    msg = TransformStamped()
    msg.header.frame_id = parent
    msg.header.stamp = time_msg(stamp_ns)
    msg.child_frame_id = child
    msg.transform.translation.x, msg.transform.translation.y = float(pose.x), float(pose.y)
    msg.transform.rotation = yaw_to_quaternion(pose.yaw)
    return msg


def odometry(
    pose: Pose2D, twist: tuple[float, float], frames: tuple[str, str], stamp_ns: int
) -> Odometry:
    """Return ``nav_msgs/Odometry``.

    Args:
        pose: The robot in the odometry frame.
        twist: ``(linear m/s, angular rad/s)`` in the robot's frame.
        frames: ``(odom_frame, base_frame)``.
        stamp_ns: Simulated time, nanoseconds.
    """
    linear, angular = twist
    odom_frame, base_frame = frames
    msg = Odometry()
    msg.header.frame_id = odom_frame
    msg.header.stamp = time_msg(stamp_ns)
    msg.child_frame_id = base_frame
    msg.pose.pose = pose_msg(pose)
    msg.twist.twist.linear.x = float(linear)
    msg.twist.twist.angular.z = float(angular)
    # A small, constant uncertainty on x, y and yaw (diagonal of the 6x6 row-major matrices).
    for i, variance in ((0, 1e-4), (7, 1e-4), (35, 1e-3)):
        msg.pose.covariance[i] = variance
        msg.twist.covariance[i] = variance
    return msg


def occupancy_grid_msg(grid: OccupancyGrid, frame_id: str, stamp_ns: int) -> OccupancyGridMsg:
    """Return ``nav_msgs/OccupancyGrid`` for a grid (row 0 at the minimum y, as the message)."""
    msg = OccupancyGridMsg()
    msg.header.frame_id = frame_id
    msg.header.stamp = time_msg(stamp_ns)
    msg.info.map_load_time = time_msg(stamp_ns)
    msg.info.resolution = float(grid.resolution)
    msg.info.width = grid.width
    msg.info.height = grid.height
    msg.info.origin.position.x = float(grid.origin_x)
    msg.info.origin.position.y = float(grid.origin_y)
    msg.info.origin.orientation.w = 1.0
    msg.data = grid.data.astype("int8").ravel().tolist()
    return msg


class StateMessages:
    """One robot's ``/tf`` and odometry messages, built once and refilled for each state.

    ``publish`` serialises a message before it returns, so the physics loop can refill the
    same objects for its next update instead of building new ones (tens of times a wall
    second); what goes out is the same as :func:`transform` and :func:`odometry` build.

    Args:
        spawn: The ``map -> odom`` transform (the robot's spawn pose).
        frames: ``(global_frame, odom_frame, base_frame)``.
    """

    def __init__(self, spawn: Pose2D, frames: tuple[str, str, str]) -> None:
        global_frame, odom_frame, base_frame = frames
        origin = Pose2D(0.0, 0.0, 0.0)
        self._map_odom = transform(global_frame, odom_frame, spawn, 0)
        self._odom_base = transform(odom_frame, base_frame, origin, 0)
        self._tf_localized = TFMessage(transforms=[self._map_odom, self._odom_base])
        self._tf_odom_only = TFMessage(transforms=[self._odom_base])
        self.odometry = odometry(origin, (0.0, 0.0), (odom_frame, base_frame), 0)

    def fill(self, odom_pose: Pose2D, twist: tuple[float, float], stamp_ns: int, *,
             localized: bool) -> TFMessage:
        """Refill the messages for a state; return the TF message to publish.

        Args:
            odom_pose: The robot in the odometry frame.
            twist: ``(linear m/s, angular rad/s)`` in the robot's frame.
            stamp_ns: Simulated time, nanoseconds.
            localized: Whether ``map -> odom`` goes out too (AMCL has a pose).

        Returns:
            The TF message (``map -> odom`` first when localised); :attr:`odometry` is
            refilled too.
        """
        sec, nanosec = split_ns(stamp_ns)
        x, y = float(odom_pose.x), float(odom_pose.y)
        qz, qw = math.sin(odom_pose.yaw / 2.0), math.cos(odom_pose.yaw / 2.0)
        for header in (self._map_odom.header, self._odom_base.header, self.odometry.header):
            header.stamp.sec, header.stamp.nanosec = sec, nanosec
        moved = self._odom_base.transform
        moved.translation.x, moved.translation.y = x, y
        moved.rotation.z, moved.rotation.w = qz, qw
        pose = self.odometry.pose.pose
        pose.position.x, pose.position.y = x, y
        pose.orientation.z, pose.orientation.w = qz, qw
        speed = self.odometry.twist.twist
        speed.linear.x, speed.angular.z = float(twist[0]), float(twist[1])
        return self._tf_localized if localized else self._tf_odom_only
