"""Nav2's behaviour-server clients: Spin, BackUp, DriveOnHeading, Wait.

Each sends one goal to Nav2's ``behavior_server`` (``spin``, ``backup``,
``drive_on_heading``, ``wait``) with Nav2's ports and defaults. As in Nav2 Jazzy, BackUp
and Wait count a recovery on the root blackboard's ``number_recoveries`` when they start,
Spin when ``is_recovery`` is true; a negative or zero ``wait_duration`` is used as its
absolute value, with a warning.

Nav2's ``Wait`` asks the ``wait`` server to wait. It is not the dwell on the node's clock
this framework had under that name before: that one is now ``Dwell`` (CHANGELOG.md).
"""

from __future__ import annotations

from sar_framework.engine.plugin import leaf
from sar_framework.engine.ports import InputPort, OutputPort

from ._bt_nodes import Nav2ActionLeaf
from ._common import count_recovery, duration_msg, optional_input, server_ports

_ALLOWANCE = InputPort("time_allowance", float, default=10.0,
                       description="Time to invoke behavior for, if exceeds considers it a "
                                   "stuck condition or failure case (seconds).")
_ERROR = OutputPort("error_code_id", int, description="The behaviour server's error code "
                                                      "(0, NONE, when it succeeded).")


def fill_straight(leaf: Nav2ActionLeaf, distance_port: str, speed_port: str) -> None:
    """Fill a BackUp/DriveOnHeading goal: x distance, speed, time allowance."""
    leaf.goal.target.x = float(leaf.ports.get(distance_port))
    leaf.goal.target.y = leaf.goal.target.z = 0.0
    leaf.goal.speed = float(leaf.ports.get(speed_port))
    leaf.goal.time_allowance = duration_msg(float(leaf.ports.get("time_allowance")))


@leaf(ports=[
    InputPort("spin_dist", float, default=1.57, description="Spin distance (radians)."),
    _ALLOWANCE,
    InputPort("is_recovery", bool, default=True,
              description="True if the action is being used as a recovery."),
    *server_ports("spin"),
    _ERROR,
])
class Spin(Nav2ActionLeaf):
    """Nav2's Spin: turn in place by ``spin_dist`` radians."""

    action_type = "nav2_msgs/action/Spin"
    SERVER = "spin"

    def on_tick(self) -> bool:
        """Fill the goal from the ports (False: fail without sending)."""
        self.goal.target_yaw = float(self.ports.get("spin_dist"))
        self.goal.time_allowance = duration_msg(float(self.ports.get("time_allowance")))
        if optional_input(self.ports, "is_recovery", True):
            count_recovery()
        return True


@leaf(ports=[
    InputPort("backup_dist", float, default=0.15, description="Total distance to backup (m)."),
    InputPort("backup_speed", float, default=0.025, description="Backup speed (m/s)."),
    _ALLOWANCE,
    *server_ports("backup"),
    _ERROR,
])
class BackUp(Nav2ActionLeaf):
    """Nav2's BackUp: drive straight backwards ``backup_dist`` metres."""

    action_type = "nav2_msgs/action/BackUp"
    SERVER = "backup"

    def on_tick(self) -> bool:
        """Fill the goal from the ports (False: fail without sending)."""
        fill_straight(self, "backup_dist", "backup_speed")
        count_recovery()
        return True


@leaf(ports=[
    InputPort("dist_to_travel", float, default=0.15, description="Distance to travel (m)."),
    InputPort("speed", float, default=0.025, description="Speed at which to travel (m/s)."),
    _ALLOWANCE,
    *server_ports("drive_on_heading"),
    _ERROR,
])
class DriveOnHeading(Nav2ActionLeaf):
    """Nav2's DriveOnHeading: drive straight ahead ``dist_to_travel`` metres."""

    action_type = "nav2_msgs/action/DriveOnHeading"
    SERVER = "drive_on_heading"

    def on_tick(self) -> bool:
        """Fill the goal from the ports (False: fail without sending)."""
        fill_straight(self, "dist_to_travel", "speed")
        return True


@leaf(ports=[
    InputPort("wait_duration", float, default=1.0, description="Wait time (s)."),
    *server_ports("wait"),
], moved={"duration": "'Wait' is Nav2's Wait (a goal to the 'wait' behaviour server, port "
                      "'wait_duration'); the dwell on the node's clock that took 'duration' "
                      "is now 'Dwell': write Dwell: {duration: ...}"})
class Wait(Nav2ActionLeaf):
    """Nav2's Wait: the ``wait`` behaviour server waits ``wait_duration`` seconds.

    Not a dwell on this node's clock: that is ``Dwell``.
    """

    action_type = "nav2_msgs/action/Wait"
    SERVER = "wait"

    def on_tick(self) -> bool:
        """Fill the goal from the ports (False: fail without sending)."""
        duration = float(self.ports.get("wait_duration"))
        if duration <= 0.0:
            self.node.get_logger().warning(
                f"Wait duration is negative or zero ({duration}). Setting to positive.")
            duration = abs(duration)
        self.goal.time = duration_msg(duration)
        count_recovery()
        return True
