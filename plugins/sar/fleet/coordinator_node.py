r"""``zone_coordinator``: the fleet's zones, allocated by sequential single-item auction.

One node in the root namespace serves every robot (the robots' ``ClaimZone``,
``CompleteZone`` and ``ReleaseZone`` leaves call it by absolute names)::

    sar-zone-coordinator --ros-args --params-file config/mission_params.yaml \\
        -p events_file:=fleet_events.jsonl

The protocol (the rules are :mod:`sar_plugins.sar.fleet.auction`'s):

1. request: a robot asks for work on ``/zone_coordinator/request_zone``;
2. notice: when open zones and waiting robots exist, a round opens: a ``ZoneNotice`` on
   ``/zone_coordinator/notices`` names the zones and the bidders; the first round waits
   (``start_wait_wall_s`` at most) until every robot of the fleet (``robots``) has asked;
3. bid: each bidder answers on ``/zone_coordinator/bid_zones`` with its Nav2 path cost per
   zone (``inf``: it cannot reach it);
4. award: once every bidder bid or ``bid_window_wall_s`` passed, the lowest bids win, one zone
   per robot; each win is a ``ZoneAward`` on ``/zone_coordinator/awards``;
5. finish: the winner says on ``/zone_coordinator/finish_zone`` that it searched the zone,
   or gives it back (it could not reach it).

Robots publish ``FleetHeartbeat`` on ``/zone_coordinator/heartbeat``; one silent for
``robot_timeout_wall_s`` (wall clock) is lost and its claims go back to auction. Every decision
is a ``FleetEvent`` (:mod:`.event_log`). Parameters:
:data:`~sar_plugins.sar.fleet.params.COORDINATOR_PARAMETERS`. Exits 2 with one line on a bad
configuration.
"""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Sequence
from typing import Any

from rclpy.clock import Clock, ClockType
from rclpy.node import Node
from sar_fleet_interfaces.msg import FleetEvent, FleetHeartbeat, ZoneAward, ZoneNotice
from sar_fleet_interfaces.srv import BidZones, FinishZone, RequestZone
from sar_plugins.sar.fleet.auction import ZoneAuction
from sar_plugins.sar.fleet.event_log import FleetEventLog
from sar_plugins.sar.fleet.params import COORDINATOR_PARAMETERS
from sar_plugins.sar.fleet.survivor_registry import Registration
from sar_plugins.sar.fleet.survivor_service import SurvivorRegistryService
from sar_plugins.sar.params import read_mission_params

from sar_framework.mission.params_file import check_params_file, params_files_from_args
from sar_framework.ros.parameters import declare_table
from sar_framework.ros.qos import latched_qos
from sar_framework.ros.serve import ServerConfigError, serve

NODE_NAME = "zone_coordinator"
PREFIX = "/zone_coordinator/"
#: How often the coordinator checks for lost robots and rounds to open or close (wall).
CHECK_PERIOD_S = 0.1
#: Notices and awards a late subscriber still receives.
HISTORY_DEPTH = 100


class ZoneCoordinator:
    """The coordinator's ROS side over one :class:`ZoneAuction`.

    Args:
        node: A node that declares its parameter files' keys (``automatically_declare_
            parameters_from_overrides``).
        source: The mission parameter file, for messages.
        locations: Where each key is set in the parameter files.

    Raises:
        ServerConfigError: A bad parameter or an events file that cannot be opened.
    """

    def __init__(self, node: Node, source: str = "parameters",
                 locations: dict[str, Any] | None = None) -> None:
        self.node = node
        values = declare_table(node, COORDINATOR_PARAMETERS, source="parameters",
                               locations=locations)
        mission = read_mission_params(node, source=source, locations=locations)
        self.timeout_s = float(values["robot_timeout_wall_s"])
        self.window_s = float(values["bid_window_wall_s"])
        fleet = values["robots"] or []
        try:
            self.auction = ZoneAuction(
                mission.zone_order, abandon_after_rounds=int(values["abandon_after_rounds"]),
                robots=fleet, start_wait_s=float(values["start_wait_wall_s"]))
        except ValueError as err:  # a repeated or empty name in robots
            raise ServerConfigError(str(err)) from None
        try:
            self.events = FleetEventLog(node, values["events_file"])
        except OSError as err:
            raise ServerConfigError(f"events_file: cannot open {values['events_file']}: "
                                    f"{err}") from None
        self._start = time.monotonic()
        self._complete = False
        self._notices = node.create_publisher(ZoneNotice, PREFIX + "notices",
                                              latched_qos(HISTORY_DEPTH))
        self._awards = node.create_publisher(ZoneAward, PREFIX + "awards",
                                             latched_qos(HISTORY_DEPTH))
        node.create_subscription(FleetHeartbeat, PREFIX + "heartbeat", self._on_heartbeat, 50)
        node.create_service(RequestZone, PREFIX + "request_zone", self._on_request)
        node.create_service(BidZones, PREFIX + "bid_zones", self._on_bid)
        node.create_service(FinishZone, PREFIX + "finish_zone", self._on_finish)
        node.create_timer(CHECK_PERIOD_S, self.check,
                          clock=Clock(clock_type=ClockType.STEADY_TIME))
        try:
            self.survivors = SurvivorRegistryService(
                node, float(values["survivor_radius_m"]), on_registered=self._registered)
        except ValueError as err:
            raise ServerConfigError(f"survivor_radius_m: {err}") from None
        node.get_logger().info(
            f"ready: {len(mission.zone_order)} zones ({', '.join(mission.zone_order)}), "
            f"robot_timeout_wall_s {self.timeout_s:g}, bid_window_wall_s {self.window_s:g}, "
            f"survivors within {values['survivor_radius_m']:g} m are one; the first round "
            f"waits up to {values['start_wait_wall_s']:g} s for "
            f"{', '.join(fleet) if fleet else 'every robot heard'}")

    def now(self) -> float:
        """Wall seconds since the coordinator started."""
        return time.monotonic() - self._start

    # -- the robots ----------------------------------------------------------------------

    def _heard(self, robot: str) -> None:
        was = self.auction.robot_state(robot)
        if not self.auction.heard(robot, self.now()):
            return
        again = "rejoined the fleet (it was lost)" if was is not None else "joined the fleet"
        reopened = self.auction.reopen_abandoned(robot)
        if reopened:
            again += f"; {', '.join(reopened)} reopened (abandoned before it came)"
            self._complete = False
        self.events.emit(FleetEvent.KIND_ROBOT_JOINED, f"{robot} {again}", robot=robot,
                         zone_ids=reopened)

    def _on_heartbeat(self, message: FleetHeartbeat) -> None:
        if message.robot:
            self._heard(message.robot)

    def _on_request(self, request: RequestZone.Request,
                    response: RequestZone.Response) -> RequestZone.Response:
        robot = request.robot
        if robot:
            self._heard(robot)
        answer = self.auction.request(robot, self.now())
        response.accepted, response.done, response.reason = (
            answer.accepted, answer.done, answer.reason)
        if not answer.accepted:
            self.node.get_logger().info(f"request from {robot!r} refused: {answer.reason}")
        self.check()
        return response

    def _on_bid(self, request: BidZones.Request,
                response: BidZones.Response) -> BidZones.Response:
        zone_ids, costs = list(request.zone_ids), [float(c) for c in request.costs]
        if request.robot:
            self._heard(request.robot)
        if len(zone_ids) != len(costs):
            reason = f"{len(zone_ids)} zone ids but {len(costs)} costs"
        else:
            reason = self.auction.bid(request.auction_id, request.robot,
                                      dict(zip(zone_ids, costs, strict=True)))
        response.accepted, response.reason = reason is None, reason or ""
        if reason is not None:
            self.node.get_logger().warning(f"bid from {request.robot!r} refused: {reason}")
            return response
        said = ", ".join(f"{z} {c:.2f}" if math.isfinite(c) else f"{z} unreachable"
                         for z, c in zip(zone_ids, costs, strict=True))
        self.events.emit(FleetEvent.KIND_BID, f"{request.robot} bids in auction "
                         f"{request.auction_id}: {said or 'nothing'}",
                         auction_id=request.auction_id, robot=request.robot,
                         zone_ids=zone_ids, costs=costs)
        self.check()
        return response

    def _on_finish(self, request: FinishZone.Request,
                   response: FinishZone.Response) -> FinishZone.Response:
        robot, zone_id = request.robot, request.zone_id
        if robot:
            self._heard(robot)
        if request.outcome not in (FinishZone.Request.SEARCHED, FinishZone.Request.GIVEN_BACK):
            reason: str | None = f"unknown outcome {request.outcome} (0 searched, 1 given back)"
        else:
            searched = request.outcome == FinishZone.Request.SEARCHED
            reason = self.auction.finish(robot, zone_id, searched=searched)
        response.accepted, response.reason = reason is None, reason or ""
        if reason is not None:
            self.node.get_logger().warning(f"finish from {robot!r} refused: {reason}")
            return response
        if searched:
            self.events.emit(FleetEvent.KIND_SEARCHED, f"{robot} searched {zone_id}",
                             robot=robot, zone_id=zone_id)
        else:
            self.events.emit(FleetEvent.KIND_GIVEN_BACK, f"{robot} gave {zone_id} back "
                             "(it cannot reach it)", robot=robot, zone_id=zone_id)
            self._abandon(self.auction.abandon_unreachable())
        self.check()
        return response

    def _registered(self, registration: Registration) -> None:
        self.events.emit(FleetEvent.KIND_SURVIVOR_REGISTERED, registration.describe(),
                         robot=registration.robot, zone_id=registration.zone_id,
                         survivor_id=registration.survivor_id,
                         position=(registration.x, registration.y, 0.0))

    # -- the coordinator's clock ---------------------------------------------------------

    def check(self) -> None:
        """Declare silent robots lost, close a finished round, open the next one."""
        now = self.now()
        lost = [] if self._complete else self.auction.expire(now, self.timeout_s)
        for robot, reopened in lost:  # robots ending their runs after the end are not news
            again = f"; {', '.join(reopened)} back to auction" if reopened else ""
            handed = self.survivors.robot_lost(robot)
            again += f"; the next finder of {', '.join(handed)} reports it" if handed else ""
            self.events.emit(FleetEvent.KIND_ROBOT_LOST, f"{robot} lost: silent for more "
                             f"than {self.timeout_s:g} s{again}", robot=robot,
                             zone_ids=reopened)
            self._abandon(self.auction.abandon_unreachable())
        if self.auction.round_ready(now, self.window_s):
            result = self.auction.close_round(now)
            for award in result.awards:
                self._awards.publish(ZoneAward(auction_id=award.auction_id, robot=award.robot,
                                               zone_id=award.zone_id, cost=award.cost))
                self.events.emit(FleetEvent.KIND_AWARD, f"auction {award.auction_id}: "
                                 f"{award.zone_id} to {award.robot} ({award.cost:.2f} m)",
                                 auction_id=award.auction_id, robot=award.robot,
                                 zone_id=award.zone_id, costs=[award.cost])
            self._abandon(result.abandoned)
        notice = self.auction.open_round(now, retry_after_s=self.window_s)
        if notice is not None:
            self._notices.publish(ZoneNotice(
                auction_id=notice.auction_id, zone_ids=list(notice.zone_ids),
                robots=list(notice.bidders), bid_window_s=self.window_s))
            self.events.emit(FleetEvent.KIND_AUCTION, f"auction {notice.auction_id}: "
                             f"{', '.join(notice.zone_ids)} to {', '.join(notice.bidders)}",
                             auction_id=notice.auction_id, zone_ids=notice.zone_ids,
                             robots=notice.bidders)
        if self.auction.done() and not self._complete:
            self._complete = True
            self.events.emit(FleetEvent.KIND_COMPLETE, "complete: every zone is searched "
                             "or abandoned")

    def _abandon(self, zone_ids: Sequence[str]) -> None:
        for zone_id in zone_ids:
            self.events.emit(FleetEvent.KIND_ABANDONED, f"{zone_id} abandoned: no live "
                             "robot can reach it", zone_id=zone_id)

    def close(self) -> None:
        """Close the events file."""
        self.events.close()


class ZoneCoordinatorNode(Node):
    """The ``zone_coordinator`` node (parameters from the ``--params-file`` arguments).

    It declares every key of its parameter files, as :func:`create_params_node` does.

    Args:
        argv: The command line, for the ``--params-file`` arguments.

    Raises:
        ValueError: A bad parameter file or value (a ``ParamsError``), or
            :class:`ServerConfigError`.
    """

    def __init__(self, argv: Sequence[str]) -> None:
        files = params_files_from_args(argv)
        locations: dict[str, Any] = {}
        for file in files:
            locations.update(check_params_file(file))
        where = locations.get("zone_order")
        source = where.file if where else (files[0] if files else "parameters")
        super().__init__(NODE_NAME, automatically_declare_parameters_from_overrides=True,
                         allow_undeclared_parameters=True)
        self.coordinator: ZoneCoordinator | None = None
        self.coordinator = ZoneCoordinator(self, source, locations)

    def destroy_node(self) -> None:
        """Close the events file, then destroy the node."""
        if self.coordinator is not None:
            self.coordinator.close()
        super().destroy_node()


def main(argv: Sequence[str] | None = None) -> None:
    """Console entry point: serve until SIGINT (exit 0), or exit 2 on a bad configuration."""
    args = list(sys.argv if argv is None else argv)
    sys.exit(serve(lambda: ZoneCoordinatorNode(args), NODE_NAME, args))


if __name__ == "__main__":
    main()
