"""A NavigateToPose server whose outcome each goal chooses, for the navigation leaf tests.

The goal's ``behavior_tree`` field is the script (the leaf passes it through from its
``behavior_tree`` param):

* ``""`` or ``succeed``: feedback for ``--delay`` seconds, then SUCCEEDED;
* ``abort``: ABORTED after ``--delay`` seconds with ``error_msg="robot stuck"``;
* ``reject``: the goal is rejected;
* ``hang``: accepted, then never finishes by itself (only a cancel ends it);
* ``answer-after-next``: accepted only once the next goal has arrived (to the client, an
  answer lost in transport), then as ``succeed``.

Logs ``ready``, then one line per event: ``goal 1: x=-3.00 y=3.00 qz=0.000 qw=1.000
frame=map script=succeed``, ``cancel requested``, ``goal canceled``, ``goal succeeded``,
``goal aborted``.
"""

import argparse
import itertools
import threading
import time

import rclpy
from _node_main import spin_until_interrupted
from nav2_msgs.action import NavigateToPose
from rclpy.action import ActionServer, CancelResponse, GoalResponse
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.node import Node


def main() -> None:
    """Serve until SIGINT."""
    parser = argparse.ArgumentParser()
    parser.add_argument("--delay", type=float, default=0.3)
    args = parser.parse_args()
    rclpy.init()
    node = Node("scripted_navigate_server")
    log = node.get_logger()
    counter = itertools.count(1)
    next_goal = threading.Event()  # set by every goal; awaited by answer-after-next
    holding = threading.Lock()  # held while an answer-after-next goal waits

    def on_goal(goal: NavigateToPose.Goal) -> GoalResponse:
        pose = goal.pose.pose
        script = goal.behavior_tree or "succeed"
        log.info(f"goal {next(counter)}: x={pose.position.x:.2f} y={pose.position.y:.2f} "
                 f"qz={pose.orientation.z:.3f} qw={pose.orientation.w:.3f} "
                 f"frame={goal.pose.header.frame_id} script={script}")
        if script == "answer-after-next" and holding.acquire(blocking=False):
            next_goal.clear()
            next_goal.wait(30.0)  # outer safety bound: a client that never resends has failed
            holding.release()
            return GoalResponse.ACCEPT
        next_goal.set()
        return GoalResponse.REJECT if script == "reject" else GoalResponse.ACCEPT

    def on_cancel(_handle: object) -> CancelResponse:
        log.info("cancel requested")
        return CancelResponse.ACCEPT

    def execute(goal_handle):
        script = goal_handle.request.behavior_tree or "succeed"
        feedback = NavigateToPose.Feedback()
        steps = round(args.delay / 0.05)  # takes at least the delay
        step = 0
        while script == "hang" or step < steps:
            if goal_handle.is_cancel_requested:
                goal_handle.canceled()
                log.info("goal canceled")
                return NavigateToPose.Result()
            feedback.distance_remaining = max(0.0, (steps - step) * 0.05)
            goal_handle.publish_feedback(feedback)
            step += 1
            time.sleep(0.05)
        if script == "abort":
            goal_handle.abort()
            log.info("goal aborted")
            return NavigateToPose.Result(error_code=1, error_msg="robot stuck")
        goal_handle.succeed()
        log.info("goal succeeded")
        return NavigateToPose.Result()

    ActionServer(
        node, NavigateToPose, "navigate_to_pose", execute_callback=execute,
        goal_callback=on_goal, cancel_callback=on_cancel,
        callback_group=ReentrantCallbackGroup(),
    )
    log.info("ready")
    spin_until_interrupted(node, threads=4)


if __name__ == "__main__":
    main()
