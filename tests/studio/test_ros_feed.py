"""The live studio's ROS feed against real rclpy publishers: statuses, events, poses and the
map reach the session; a mission that starts again starts the session over; bad messages
are dropped."""

from __future__ import annotations

import json

import pytest
from sar_testing.spin import ros_node, spin_until

from sar_framework.events.event import EventKind, MissionEvent
from sar_framework.studio.ros_feed import LiveFeed
from sar_framework.studio.session import LIVE, Session

pytestmark = pytest.mark.ros

WORLD = {"grid": None, "places": [], "base": None}


def status_text(tick: int, leaf: str) -> str:
    return json.dumps({"format": 1, "tree": "demo", "tick": tick, "sim_s": float(tick),
                       "status": "RUNNING", "complete": False, "zone": None,
                       "nodes": [["0", "Root", "sequence", "RUNNING", "", True],
                                 ["0.0", "Leaf", "Wait", leaf, "", True]],
                       "blackboard": {}})


def transform(frame: str, child: str, x: float, stamp_s: float):
    from geometry_msgs.msg import TransformStamped

    t = TransformStamped()
    t.header.frame_id, t.child_frame_id = frame, child
    t.header.stamp.sec = int(stamp_s)
    t.transform.translation.x = x
    t.transform.rotation.w = 1.0
    return t


def test_a_mission_on_the_domain_fills_the_session() -> None:
    from nav_msgs.msg import OccupancyGrid
    from std_msgs.msg import String
    from tf2_msgs.msg import TFMessage

    from sar_framework.ros.qos import latched_qos
    from sar_framework.runner.event_topic import event_qos, to_message
    from sar_framework.runner.tree_status import STATUS_HISTORY, STATUS_TOPIC

    session = Session(LIVE, None, WORLD, "live")
    feed = LiveFeed(session).start()
    try:
        with ros_node("fake_mission") as (node, executor):
            from sar_interfaces.msg import MissionEvent as EventMsg

            status = node.create_publisher(String, STATUS_TOPIC, latched_qos(STATUS_HISTORY))
            events = node.create_publisher(EventMsg, "/sar_mission/events", event_qos())
            tf = node.create_publisher(TFMessage, "/tf", 100)
            grid = node.create_publisher(OccupancyGrid, "/map", latched_qos())
            spin_until(executor, lambda: status.get_subscription_count() > 0
                       and tf.get_subscription_count() > 0, 15)
            for tick, leaf in ((1, "RUNNING"), (2, "FAILURE")):
                status.publish(String(data=status_text(tick, leaf)))
            status.publish(String(data="not a status"))
            events.publish(to_message(MissionEvent(EventKind.FAILURE, seq=1, sim_s=2.0,
                                                   node_uid="0.0", message="broke")))
            message = OccupancyGrid()
            message.info.width, message.info.height, message.info.resolution = 2, 1, 0.5
            message.data = [100, 0]
            grid.publish(message)
            for x in (0.0, 1.0):
                tf.publish(TFMessage(transforms=[transform("map", "odom", 0.5, 1.0),
                                                 transform("odom", "base_link", x, 2.0)]))
                spin_until(executor, lambda: False, 0.1)

            def filled() -> bool:
                with session.lock:
                    return (len(session.timeline.statuses) == 2
                            and len(session.timeline.events) == 1
                            and len(session.timeline.poses) == 2
                            and session.world["grid"] is not None)

            assert spin_until(executor, filled, 15), session.frame()
            frame = session.frame()
            assert frame["nodes"]["0.0"][0] == "FAILURE"
            assert frame["robot"] == [1.5, 0.0, 0.0]  # odom is 0.5 m along map's x
            assert frame["reasons"][0]["message"] == "broke"
            assert session.world["grid"]["walls"] == [[0, 0, 1]]
            assert session.tree["source"] == "status"
            assert session.version >= 6  # every message told the server's tabs
            # a new mission on the domain: tick 1 again
            status.publish(String(data=status_text(1, "RUNNING")))
            assert spin_until(executor, lambda: session.frame()["tick"] == 1, 15)
            assert len(session.timeline.statuses) == 1
            assert session.frame()["reasons"] == []
    finally:
        feed.stop()


def test_the_feed_asks_the_runner_to_reload_and_a_swap_redraws_the_tree() -> None:
    from concurrent.futures import ThreadPoolExecutor

    from std_msgs.msg import String
    from std_srvs.srv import Trigger

    from sar_framework.ros.qos import latched_qos
    from sar_framework.runner.event_topic import event_qos, to_message
    from sar_framework.runner.tree_status import STATUS_HISTORY, STATUS_TOPIC

    session = Session(LIVE, None, WORLD, "live")
    drawn: list[int] = []
    session.draw_file = lambda: drawn.append(1)  # None: nothing to draw, but asked
    learnt: list[str] = []
    session.learn_tree = learnt.append  # no tree file given: the runner's, once it runs
    feed = LiveFeed(session).start()
    asked: list[int] = []

    def answer(_request, response):
        asked.append(1)
        response.success, response.message = True, "Tree swapped from t.yaml: 1 added (X)"
        return response

    try:
        with ros_node("sar_mission_runner") as (node, executor), \
                ThreadPoolExecutor(max_workers=2) as pool:
            from sar_interfaces.msg import MissionEvent as EventMsg

            node.declare_parameter("tree", "trees/t.yaml")
            node.create_service(Trigger, "~/reload", answer)
            events = node.create_publisher(EventMsg, "/sar_mission/events", event_qos())
            status = node.create_publisher(String, STATUS_TOPIC, latched_qos(STATUS_HISTORY))
            status.publish(String(data=status_text(1, "RUNNING")))
            assert spin_until(executor, lambda: learnt == ["trees/t.yaml"], 20)
            ticked = pool.submit(feed.ticked_tree)
            reloaded = pool.submit(feed.reload)
            assert spin_until(executor, lambda: ticked.done() and reloaded.done(), 20)
            assert ticked.result() == "trees/t.yaml"
            assert reloaded.result() == (True, "Tree swapped from t.yaml: 1 added (X)")
            assert asked == [1]
            spin_until(executor, lambda: events.get_subscription_count() > 0, 15)
            events.publish(to_message(MissionEvent(EventKind.TREE_SWAPPED, seq=1, sim_s=3.0,
                                                   message="Tree swapped")))
            assert spin_until(executor, lambda: drawn == [1], 15)
            assert session.frame()["reasons"][0]["kind"] == "tree_swapped"
    finally:
        feed.stop()
