"""ClaimZone: win the robot's next zone in the fleet's auction.

The robot's side of the coordinator's protocol (:mod:`sar_plugins.sar.fleet.coordinator_node`):
ask for work, bid the robot's own Nav2 path cost for every zone each round announces, and
take the zone once awarded. From ``setup()`` on, a wall timer publishes the robot's
heartbeat on ``/zone_coordinator/heartbeat``, so the coordinator knows the robot is alive
whatever the tree is doing (a SIGKILLed runner falls silent).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from py_trees.common import Status

from sar_framework.engine.plugin import Param, leaf
from sar_framework.leaves import GoalBatch, PolledServiceCall, RosLeaf, service_timeout_params

from ._fleet import COORDINATOR_PARAM, robot_name
from ._path_costs import PathCosts

if TYPE_CHECKING:
    from sar_plugins.sar.zone_manager import ZoneManager

#: Notices, awards and events a late subscriber still receives (the coordinator's depths).
HISTORY_DEPTH = 100
EVENTS_DEPTH = 1000
#: Wall seconds between two heartbeats: well inside the coordinator's robot_timeout_wall_s.
HEARTBEAT_PERIOD_WALL_S = 0.5
NO_WORK = "no work left: every zone is searched or abandoned"


@leaf(
    params=[
        COORDINATOR_PARAM,
        Param("action_name", str, default="compute_path_to_pose",
              description="This robot's Nav2 ComputePathToPose action (relative)."),
        Param("frame_id", str, default="map", description="Frame of the zone poses."),
        *service_timeout_params(),
    ],
    context=["zone_manager"],
)
class ClaimZone(RosLeaf):
    """Ask the zone coordinator for work and bid until a zone is won.

    RUNNING while waiting for a round, planning the bids and waiting for the award;
    SUCCESS once this robot wins a zone, which becomes the ZoneManager's current zone
    (``ZoneManager.claim``); FAILURE when no work is left (every zone searched or
    abandoned), when the coordinator refuses the request, or on the service bounds. Each
    bid is the length of the robot's Nav2 path to the zone (``inf``: no path).

    Args:
        name: The behaviour's name.
        zone_manager: The mission's shared zone state.
        server_name: The coordinator's name (absolute, fleet-wide).
        action_name: The robot's ComputePathToPose action.
        frame_id: Frame of the zone poses.
        heartbeat_period_wall_s: Wall seconds between two heartbeats (not a tree
            parameter: a leaf's durations are ROS time; this one must not be).
        server_timeout_s: Bound on waiting for the coordinator's services.
        response_timeout_s: Bound on waiting for their answers.
    """

    def __init__(self, name: str, *, zone_manager: ZoneManager,
                 server_name: str, action_name: str, frame_id: str, server_timeout_s: float,
                 response_timeout_s: float,
                 heartbeat_period_wall_s: float = HEARTBEAT_PERIOD_WALL_S) -> None:
        super().__init__(name)
        self.zone_manager = zone_manager
        self.prefix = server_name.rstrip("/")
        self.action_name = action_name
        self.frame_id = frame_id
        self.heartbeat_period_wall_s = heartbeat_period_wall_s
        self.server_timeout_s = server_timeout_s
        self.response_timeout_s = response_timeout_s
        self.robot = ""
        self._ros: dict[str, Any] = {}
        self._request: PolledServiceCall | None = None
        self._bid: PolledServiceCall | None = None
        self._notices: list[Any] = []
        self._awards: list[Any] = []
        self._complete = False  # the coordinator said no work is left: final
        self._last_notice = 0
        self._phase = "request"
        self._round: Any = None
        self._costs: PathCosts | None = None
        self._bid_costs: dict[str, float] = {}
        self._bid_rounds: set[int] = set()

    def setup(self, **kwargs: Any) -> None:
        """Create the clients and subscriptions; start the heartbeat.

        Args:
            **kwargs: Must hold ``node``.
        """
        super().setup(**kwargs)
        from nav2_msgs.action import ComputePathToPose
        from rclpy.clock import Clock, ClockType
        from sar_fleet_interfaces.msg import FleetEvent, FleetHeartbeat, ZoneAward, ZoneNotice
        from sar_fleet_interfaces.srv import BidZones, RequestZone

        from sar_framework.ros.qos import latched_qos

        node = self.node
        self.robot = robot_name(node)
        calls = {"server_timeout_s": self.server_timeout_s,
                 "response_timeout_s": self.response_timeout_s}
        self._request = PolledServiceCall(node, RequestZone, f"{self.prefix}/request_zone",
                                          **calls)
        self._bid = PolledServiceCall(node, BidZones, f"{self.prefix}/bid_zones", **calls)
        heartbeat = node.create_publisher(FleetHeartbeat, f"{self.prefix}/heartbeat", 10)

        def beat() -> None:
            heartbeat.publish(FleetHeartbeat(robot=self.robot))

        self._ros = {
            "planner": GoalBatch(node, ComputePathToPose, self.action_name),
            "heartbeat": heartbeat,
            "timer": node.create_timer(self.heartbeat_period_wall_s, beat,
                                       clock=Clock(clock_type=ClockType.STEADY_TIME)),
            "notices": node.create_subscription(ZoneNotice, f"{self.prefix}/notices",
                                                self._notices.append,
                                                latched_qos(HISTORY_DEPTH)),
            "awards": node.create_subscription(ZoneAward, f"{self.prefix}/awards",
                                               self._awards.append, latched_qos(HISTORY_DEPTH)),
            "events": node.create_subscription(FleetEvent, f"{self.prefix}/events",
                                               self._on_event, latched_qos(EVENTS_DEPTH)),
            "bid_type": BidZones,
            "request_type": RequestZone,
        }
        beat()

    def _on_event(self, event: Any) -> None:
        if event.kind == "complete":
            self._complete = True

    def initialise(self) -> None:
        """Start asking for work."""
        self.reset_latch()
        self._phase = "request"
        self._round = self._costs = None
        self._bid_rounds = set()
        if self._complete:  # decided at once, so a reactive parent does not halt the way home
            self.latch(False, NO_WORK, log=False)
            return
        self._calls()[0].start()
        self.feedback_message = f"{self.robot} asking for work"

    def update(self) -> Status:
        """Advance the request, the bids and the wait for an award without blocking."""
        if self._done:
            return self.verdict()
        request, bid = self._calls()
        if self._phase == "request":
            result = request.poll(lambda: self._ros["request_type"].Request(robot=self.robot))
            if result is None:
                return Status.RUNNING
            if result.error is not None:
                return self.latch(False, f"cannot ask for work: {result.error}")
            if result.response.done:
                self._complete = True
                return self.latch(False, NO_WORK)
            if not result.response.accepted:
                return self.latch(False, f"the coordinator refused: {result.response.reason}")
            self._phase = "wait"
            self.feedback_message = f"{self.robot} waiting for an auction"
        won = self._won()
        if won is not None:
            return won
        if self._complete:
            return self.latch(False, NO_WORK)
        if self._phase == "wait":
            self._maybe_plan()
        if self._phase == "plan":
            assert self._costs is not None
            costs = self._costs.poll()
            if costs is None:
                return Status.RUNNING
            self._bid_rounds.add(self._round.auction_id)
            if not costs:  # the planner answered for no zone: wait for the next round
                self._phase = "wait"
                self.feedback_message = (f"{self.robot}: no planner answer for auction "
                                         f"{self._round.auction_id}; no bid, waiting")
                return Status.RUNNING
            self._bid_costs = costs
            bid.start()
            self._phase = "bid"
        if self._phase == "bid":
            result = bid.poll(self._bid_request)
            if result is None:
                return Status.RUNNING
            if result.error is not None or not result.response.accepted:
                why = result.error or result.response.reason
                self.node.get_logger().warning(f"bid in auction {self._round.auction_id} "
                                               f"not taken: {why}")
            self._phase = "wait"
            self.feedback_message = f"{self.robot} bid in auction {self._round.auction_id}"
        return Status.RUNNING

    def terminate(self, new_status: Status) -> None:
        """Drop the calls still waiting for an answer when halted.

        Args:
            new_status: The status the leaf is moving to.
        """
        if not self._done and self._request is not None and self._bid is not None:
            self._request.abandon()
            self._bid.abandon()

    def shutdown(self) -> None:
        """Stop the heartbeat and destroy the clients."""
        node = self._node
        if node is None or not self._ros:
            return
        node.destroy_timer(self._ros["timer"])
        self._ros["planner"].destroy()
        for key in ("notices", "awards", "events"):
            node.destroy_subscription(self._ros[key])
        node.destroy_publisher(self._ros["heartbeat"])
        for call in self._calls():
            call.destroy()
        self._ros = {}

    # -- helpers -------------------------------------------------------------------------

    def _calls(self) -> tuple[PolledServiceCall, PolledServiceCall]:
        if self._request is None or self._bid is None:
            raise RuntimeError(f"ClaimZone '{self.name}' used before setup(node=...)")
        return self._request, self._bid

    def _won(self) -> Status | None:
        awards, self._awards[:] = list(self._awards), []
        for award in awards:
            if award.robot == self.robot and award.auction_id in self._bid_rounds:
                self.zone_manager.claim(award.zone_id)
                return self.latch(True, f"{self.robot} won {award.zone_id} in auction "
                                         f"{award.auction_id} ({award.cost:.2f} m)")
        return None

    def _maybe_plan(self) -> None:
        notices, self._notices[:] = list(self._notices), []
        fresh = [n for n in notices if n.auction_id > self._last_notice]
        if fresh:
            self._last_notice = max(n.auction_id for n in fresh)
        mine = [n for n in fresh if self.robot in n.robots]
        if not mine:
            return
        self._round = max(mine, key=lambda n: n.auction_id)
        zones = {}
        for zone_id in self._round.zone_ids:
            try:
                zones[zone_id] = self.zone_manager.zone(zone_id)
            except KeyError:
                self.node.get_logger().warning(f"auction {self._round.auction_id}: "
                                               f"{zone_id} is not in this robot's mission")
        bound = max(0.1, 0.75 * float(self._round.bid_window_s))
        self._costs = PathCosts(self._ros["planner"], self.frame_id,
                                zones=zones, bound_wall_s=bound,
                                stamp=self.node.get_clock().now().to_msg())
        self._phase = "plan"
        self.feedback_message = f"{self.robot} planning bids for auction " \
                                f"{self._round.auction_id}"

    def _bid_request(self) -> Any:
        request = self._ros["bid_type"].Request()
        request.auction_id = self._round.auction_id
        request.robot = self.robot
        request.zone_ids = list(self._bid_costs)
        request.costs = [float(c) for c in self._bid_costs.values()]
        said = ", ".join(f"{z} {c:.2f}" if math.isfinite(c) else f"{z} unreachable"
                         for z, c in self._bid_costs.items())
        self.node.get_logger().info(f"auction {self._round.auction_id}: bidding {said}")
        return request
