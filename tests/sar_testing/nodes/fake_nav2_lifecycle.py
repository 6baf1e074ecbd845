"""A fake Nav2 start-up surface: lifecycle ``get_state`` for amcl and bt_navigator, and an
AMCL that answers ``/initialpose`` on ``/amcl_pose``.

Options (argv):
    --bt-active-after S   bt_navigator reports "inactive" for S seconds, then ACTIVE
    --bt-never-active     bt_navigator always reports "inactive"
    --ignore-initialpose  never publish /amcl_pose
    --bt-drop-first N     leave bt_navigator's first N get_state requests unanswered (what
                          a reply lost by DDS looks like to the client)

Logs ``ready`` once serving, ``initialpose x=.. y=.. yaw=.. frame=..`` per seed, and
``bt_navigator answered inactive``/``active`` whenever its answer changes.
"""

import argparse
import math
import threading

import rclpy
import rclpy.task
from _node_main import spin_until_interrupted
from geometry_msgs.msg import PoseWithCovarianceStamped
from lifecycle_msgs.msg import State
from lifecycle_msgs.srv import GetState
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy


def main() -> None:
    """Serve until SIGINT."""
    parser = argparse.ArgumentParser()
    parser.add_argument("--bt-active-after", type=float, default=0.0)
    parser.add_argument("--bt-never-active", action="store_true")
    parser.add_argument("--ignore-initialpose", action="store_true")
    parser.add_argument("--bt-drop-first", type=int, default=0)
    options, ros_args = parser.parse_known_args()
    rclpy.init(args=ros_args)
    amcl = Node("amcl")
    bt = Node("bt_navigator")
    active_now = threading.Event()  # set once --bt-active-after has passed
    if options.bt_active_after > 0:
        threading.Timer(options.bt_active_after, active_now.set).start()
    else:
        active_now.set()
    answered: list[bool] = []

    def state(active: bool) -> GetState.Response:
        response = GetState.Response()
        if active:
            response.current_state = State(id=State.PRIMARY_STATE_ACTIVE, label="active")
        else:
            response.current_state = State(id=State.PRIMARY_STATE_INACTIVE, label="inactive")
        return response

    def amcl_state(_req: GetState.Request, _resp: GetState.Response) -> GetState.Response:
        return state(True)

    asked = [0]

    async def bt_state(_req: GetState.Request, _resp: GetState.Response) -> GetState.Response:
        asked[0] += 1
        if asked[0] <= options.bt_drop_first:
            bt.get_logger().info(f"get_state request {asked[0]} left unanswered")
            await rclpy.task.Future()  # never done: no reply is ever sent
        active = not options.bt_never_active and active_now.is_set()
        if answered[-1:] != [active]:
            answered.append(active)
            bt.get_logger().info(f"bt_navigator answered {'active' if active else 'inactive'}")
        return state(active)

    latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL)
    pose_pub = amcl.create_publisher(PoseWithCovarianceStamped, "/amcl_pose", latched)

    def on_initial_pose(msg: PoseWithCovarianceStamped) -> None:
        q = msg.pose.pose.orientation
        yaw = 2.0 * math.atan2(q.z, q.w)
        p = msg.pose.pose.position
        amcl.get_logger().info(
            f"initialpose x={p.x:.2f} y={p.y:.2f} yaw={yaw:.2f} frame={msg.header.frame_id}")
        if not options.ignore_initialpose:
            pose_pub.publish(msg)

    amcl.create_subscription(PoseWithCovarianceStamped, "/initialpose", on_initial_pose, 10)
    amcl.create_service(GetState, "/amcl/get_state", amcl_state)
    # Reentrant: a request left pending must not hold the later ones back.
    bt.create_service(GetState, "/bt_navigator/get_state", bt_state,
                      callback_group=ReentrantCallbackGroup())
    amcl.get_logger().info("ready")
    spin_until_interrupted(amcl, bt)


if __name__ == "__main__":
    main()
