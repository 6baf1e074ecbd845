"""The fleet's zone ledger and its sequential single-item auction (no ROS).

The zone coordinator (:mod:`sar_plugins.sar.fleet.coordinator_node`) keeps one
:class:`ZoneAuction`; every fact it learns from the robots goes in, every decision comes
out. Times are plain seconds given by the caller (the node's wall clock), so the rules are
tested without ROS::

    auction = ZoneAuction(["zone_a", "zone_b"])
    auction.request("robot1", now=0.0)
    notice = auction.open_round(now=0.0)           # zone_a, zone_b to robot1
    auction.bid(notice.auction_id, "robot1", {"zone_a": 4.2, "zone_b": 7.0})
    result = auction.close_round()                 # robot1 wins zone_a at 4.2
    auction.finish("robot1", "zone_a", searched=True)

Zones are open, claimed (by a robot), searched (by a robot) or abandoned (no live robot
can reach it). Robots are idle (known, not asking), waiting (asked for work), busy (hold a
claim) or lost (silent for longer than the coordinator's timeout).

A round: the open zones and the waiting live robots as bidders; it closes when every bidder
has bid or the bid window has passed; then the lowest ``(cost, robot, zone)`` among the
finite bids wins, that robot and zone leave, and so on (one zone per robot per round: SSI).
The fleet starts together: the first round opens only once every robot of the fleet (the
names given, else every robot heard so far) has asked for work or is lost, or ``start_wait_s``
after the first robot asked, with the robots waiting then.
Searched zones and zones claimed by a live robot are never offered. A lost robot's claim
goes back to open. A robot that gave a zone back never bids on it again. A zone is
abandoned when every live robot has given it back, or when every live robot bid ``inf``
for it (cannot reach it; a zone left out of a bid is unknown, not unreachable) in
``abandon_after_rounds`` rounds in a row; it
reopens when a robot joins (or rejoins) that has not given it back.
"No work left" (:meth:`ZoneAuction.done`): every zone searched or abandoned.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from enum import Enum


class ZoneState(Enum):
    """Where a zone stands."""

    OPEN = "open"
    CLAIMED = "claimed"
    SEARCHED = "searched"
    ABANDONED = "abandoned"


class RobotState(Enum):
    """Where a robot stands."""

    IDLE = "idle"
    WAITING = "waiting"
    BUSY = "busy"
    LOST = "lost"


@dataclass(frozen=True)
class Notice:
    """An auction round opened: ``bidders`` bid on ``zone_ids``."""

    auction_id: int
    zone_ids: tuple[str, ...]
    bidders: tuple[str, ...]


@dataclass(frozen=True)
class Award:
    """``robot`` won ``zone_id`` in round ``auction_id`` with its bid ``cost`` (metres)."""

    auction_id: int
    robot: str
    zone_id: str
    cost: float


@dataclass(frozen=True)
class RoundResult:
    """What closing a round decided: the awards, then the zones abandoned."""

    auction_id: int
    awards: tuple[Award, ...]
    abandoned: tuple[str, ...]


@dataclass(frozen=True)
class RequestAnswer:
    """The answer to a robot asking for work (the fields of ``RequestZone``'s response)."""

    accepted: bool
    done: bool
    reason: str = ""


@dataclass
class _Robot:
    state: RobotState = RobotState.IDLE
    last_heard: float = 0.0
    given_back: set[str] = field(default_factory=set)


@dataclass
class _Round:
    notice: Notice
    opened: float
    bids: dict[str, dict[str, float]] = field(default_factory=dict)


class ZoneAuction:
    """The zone ledger and its rounds.

    Args:
        zone_ids: The mission's zones, in its order (unique, non-empty).
        abandon_after_rounds: Rounds in a row in which every live robot bid and none could
            reach a zone before it is abandoned (>= 1).
        robots: The fleet: the robots the first round waits for (empty: every robot heard
            so far).
        start_wait_s: The longest the first round waits for them, from the first robot
            asking for work (>= 0; 0: it does not wait).

    Raises:
        ValueError: No zones, an empty or repeated zone id or robot name,
            ``abandon_after_rounds`` < 1 or ``start_wait_s`` < 0.
    """

    def __init__(self, zone_ids: Sequence[str], *, abandon_after_rounds: int = 2,
                 robots: Sequence[str] = (), start_wait_s: float = 0.0) -> None:
        if not zone_ids:
            raise ValueError("zone_ids: empty (the auction needs at least one zone)")
        _check_names("zone_ids", zone_ids)
        _check_names("robots", robots)
        if abandon_after_rounds < 1:
            raise ValueError(f"abandon_after_rounds must be >= 1, got {abandon_after_rounds}")
        if not start_wait_s >= 0:
            raise ValueError(f"start_wait_s must be >= 0, got {start_wait_s}")
        self._order = tuple(zone_ids)
        self._zones = {zone_id: ZoneState.OPEN for zone_id in self._order}
        self._holder: dict[str, str] = {}  # zone -> robot, for claimed and searched zones
        self._robots: dict[str, _Robot] = {}
        self._abandon_after = abandon_after_rounds
        self._unreachable: dict[str, int] = {}
        self._round: _Round | None = None
        self._next_id = 1
        self._last_key: tuple[tuple[str, ...], tuple[str, ...]] | None = None
        self._last_closed = -math.inf
        self._fleet = tuple(robots)
        self._start_wait = start_wait_s
        self._first_asked: float | None = None

    # -- what the ledger knows -----------------------------------------------------------

    def zone_state(self, zone_id: str) -> ZoneState:
        """The state of ``zone_id`` (KeyError for an unknown zone)."""
        return self._zones[zone_id]

    def holder(self, zone_id: str) -> str | None:
        """The robot that claimed or searched ``zone_id`` (None when open or abandoned)."""
        return self._holder.get(zone_id)

    def robot_state(self, robot: str) -> RobotState | None:
        """The state of ``robot``, None when it never made contact."""
        known = self._robots.get(robot)
        return known.state if known else None

    def live_robots(self) -> tuple[str, ...]:
        """The robots not lost."""
        return tuple(r for r, s in self._robots.items() if s.state is not RobotState.LOST)

    def claims(self, robot: str) -> tuple[str, ...]:
        """The zones ``robot`` holds now."""
        return tuple(z for z in self._order
                     if self._zones[z] is ZoneState.CLAIMED and self._holder[z] == robot)

    def open_zones(self) -> tuple[str, ...]:
        """The open zones, in the mission's order."""
        return tuple(z for z in self._order if self._zones[z] is ZoneState.OPEN)

    def done(self) -> bool:
        """Whether no work is left: every zone searched or abandoned."""
        return all(s in (ZoneState.SEARCHED, ZoneState.ABANDONED) for s in self._zones.values())

    # -- what the robots say -------------------------------------------------------------

    def heard(self, robot: str, now: float) -> bool:
        """Record a sign of life (a heartbeat or any request) from ``robot``.

        Returns:
            True when the robot is new or comes back after being lost (it is then idle).

        Raises:
            ValueError: An empty robot name.
        """
        if not robot:
            raise ValueError("empty robot name")
        known = self._robots.get(robot)
        if known is None:
            self._robots[robot] = _Robot(last_heard=now)
            return True
        known.last_heard = max(known.last_heard, now)
        if known.state is RobotState.LOST:
            known.state = RobotState.IDLE
            return True
        return False

    def request(self, robot: str, now: float) -> RequestAnswer:
        """``robot`` asks for work; it bids from the next round on.

        A robot asking while it holds a claim has lost track of it (restarted): the claim
        goes back to open.
        """
        if not robot:
            return RequestAnswer(False, self.done(), "empty robot name")
        self.heard(robot, now)
        if self.done():
            return RequestAnswer(False, True, "no work left: every zone is searched or abandoned")
        for zone_id in self.claims(robot):
            self._reopen(zone_id)
        self._robots[robot].state = RobotState.WAITING
        if self._first_asked is None:
            self._first_asked = now
        return RequestAnswer(True, False)

    def bid(self, auction_id: int, robot: str, costs: Mapping[str, float]) -> str | None:
        """Record ``robot``'s bids in round ``auction_id`` (a repeated bid replaces it).

        Args:
            auction_id: The round.
            robot: The bidder.
            costs: Zone -> metres; ``inf`` means it cannot reach it; a zone left out is
                no bid on it (the robot does not know), never evidence that it cannot.

        Returns:
            None when accepted, else why the bid is refused.
        """
        current = self._round
        if current is None or current.notice.auction_id != auction_id:
            now_open = f"auction {current.notice.auction_id} is open" if current else \
                "no auction is open"
            return f"auction {auction_id} is not open ({now_open})"
        if robot not in current.notice.bidders:
            return (f"{robot or '(empty name)'} is not a bidder of auction {auction_id} "
                    f"(bidders: {', '.join(current.notice.bidders)})")
        checked: dict[str, float] = {}
        for zone_id, cost in costs.items():
            if zone_id not in current.notice.zone_ids:
                return f"zone {zone_id!r} is not offered in auction {auction_id}"
            if isinstance(cost, bool) or not isinstance(cost, (int, float)) or math.isnan(cost) \
                    or cost < 0:
                return f"cost for {zone_id} must be a number >= 0 or inf, got {cost!r}"
            checked[zone_id] = float(cost)
        current.bids[robot] = checked
        return None

    def finish(self, robot: str, zone_id: str, *, searched: bool) -> str | None:
        """``robot`` is done with ``zone_id``: it searched it, or gives it back.

        Returns:
            None when accepted, else why refused (unknown zone, not held by ``robot``).
        """
        if zone_id not in self._zones:
            return f"unknown zone {zone_id!r} (zones: {', '.join(self._order)})"
        state, holder = self._zones[zone_id], self._holder.get(zone_id)
        if state is not ZoneState.CLAIMED or holder != robot:
            held = f"{state.value} by {holder}" if holder else state.value
            return f"{robot or '(empty name)'} does not hold {zone_id} (it is {held})"
        self._robots[robot].state = RobotState.IDLE
        if searched:
            self._zones[zone_id] = ZoneState.SEARCHED
        else:
            self._robots[robot].given_back.add(zone_id)
            self._reopen(zone_id)
        return None

    # -- the coordinator's clock ---------------------------------------------------------

    def expire(self, now: float, timeout_s: float) -> list[tuple[str, tuple[str, ...]]]:
        """Declare lost every live robot silent for more than ``timeout_s``.

        Returns:
            ``(robot, the zones it held, now open again)`` per robot lost.
        """
        lost = []
        for robot, known in self._robots.items():
            if known.state is not RobotState.LOST and now - known.last_heard > timeout_s:
                lost.append((robot, self.lose(robot)))
        return lost

    def lose(self, robot: str) -> tuple[str, ...]:
        """Declare ``robot`` lost: its claims go back to open; return them."""
        known = self._robots[robot]
        known.state = RobotState.LOST
        reopened = self.claims(robot)
        for zone_id in reopened:
            self._reopen(zone_id)
        if self._round is not None:
            self._round.bids.pop(robot, None)
        return reopened

    def abandon_unreachable(self) -> tuple[str, ...]:
        """Abandon the open zones every live robot gave back; return them."""
        live = [self._robots[r] for r in self.live_robots()]
        out = tuple(z for z in self.open_zones()
                    if live and all(z in r.given_back for r in live))
        for zone_id in out:
            self._zones[zone_id] = ZoneState.ABANDONED
        return out

    def reopen_abandoned(self, robot: str) -> tuple[str, ...]:
        """Reopen the abandoned zones ``robot`` never gave back; return them.

        For a robot that just joined (or rejoined): "no live robot can reach it" was said
        without it. Called by the coordinator whenever :meth:`heard` returns True.
        """
        given_back = self._robots[robot].given_back if robot in self._robots else set()
        out = tuple(z for z in self._order
                    if self._zones[z] is ZoneState.ABANDONED and z not in given_back)
        for zone_id in out:
            self._zones[zone_id] = ZoneState.OPEN
            self._unreachable.pop(zone_id, None)
        return out

    def open_round(self, now: float, *, retry_after_s: float = 0.0) -> Notice | None:
        """Open a round when none is open and there is something to bid on.

        The first round waits for the fleet (:meth:`fleet_started`). A round with the same
        zones and bidders as the last one (all of whom could not reach anything) opens only
        ``retry_after_s`` after that one closed.

        Returns:
            The notice, or None when no round opens.
        """
        if self._round is not None or self.done():
            return None
        waiting = [r for r, s in self._robots.items() if s.state is RobotState.WAITING]
        zones = tuple(z for z in self.open_zones()
                      if any(z not in self._robots[r].given_back for r in waiting))
        bidders = tuple(r for r in waiting
                        if any(z not in self._robots[r].given_back for z in zones))
        if not zones or not bidders or not self.fleet_started(now):
            return None
        key = (zones, bidders)
        if key == self._last_key and now - self._last_closed < retry_after_s:
            return None
        notice = Notice(self._next_id, zones, bidders)
        self._next_id += 1
        self._round = _Round(notice, now)
        return notice

    def fleet_started(self, now: float) -> bool:
        """Whether rounds may open: one did, the whole fleet asked, or the start wait passed.

        The fleet's robots count as having asked when waiting or lost (a lost robot never
        holds the others back); a named robot never heard has not asked.
        """
        if self._next_id > 1 or self._first_asked is None \
                or now - self._first_asked >= self._start_wait:
            return True
        fleet = self._fleet or tuple(self._robots)
        return all(r in self._robots
                   and self._robots[r].state in (RobotState.WAITING, RobotState.LOST)
                   for r in fleet)

    def round_ready(self, now: float, window_s: float) -> bool:
        """Whether the open round may close: every live bidder bid, or the window passed."""
        current = self._round
        if current is None:
            return False
        live = [r for r in current.notice.bidders
                if self._robots[r].state is RobotState.WAITING]
        return all(r in current.bids for r in live) or now - current.opened >= window_s

    def close_round(self, now: float = 0.0) -> RoundResult:
        """Close the open round: award lowest bids first, one zone per robot.

        Raises:
            RuntimeError: No round is open.
        """
        current = self._round
        if current is None:
            raise RuntimeError("close_round(): no auction is open")
        self._round = None
        self._last_closed = now
        notice = current.notice
        self._last_key = (notice.zone_ids, notice.bidders)
        pairs = sorted(
            (cost, robot, zone_id)
            for robot, costs in current.bids.items()
            if self._robots[robot].state is RobotState.WAITING
            for zone_id, cost in costs.items()
            if math.isfinite(cost) and self._zones[zone_id] is ZoneState.OPEN
            and zone_id not in self._robots[robot].given_back)
        awards: list[Award] = []
        for cost, robot, zone_id in pairs:
            if self._robots[robot].state is not RobotState.WAITING \
                    or self._zones[zone_id] is not ZoneState.OPEN:
                continue
            self._zones[zone_id] = ZoneState.CLAIMED
            self._holder[zone_id] = robot
            self._robots[robot].state = RobotState.BUSY
            awards.append(Award(notice.auction_id, robot, zone_id, cost))
        return RoundResult(notice.auction_id, tuple(awards), self._count_unreachable(current))

    # -- helpers -------------------------------------------------------------------------

    def _count_unreachable(self, closed: _Round) -> tuple[str, ...]:
        abandoned = list(self.abandon_unreachable())
        live = [(r, self._robots[r]) for r in self.live_robots()]
        for zone_id in closed.notice.zone_ids:
            if self._zones[zone_id] is not ZoneState.OPEN:
                self._unreachable.pop(zone_id, None)
                continue
            nobody = all(
                zone_id in known.given_back or not math.isfinite(
                    closed.bids.get(robot, {}).get(zone_id, 0.0))
                for robot, known in live)
            if not nobody:
                self._unreachable[zone_id] = 0
                continue
            self._unreachable[zone_id] = self._unreachable.get(zone_id, 0) + 1
            if self._unreachable[zone_id] >= self._abandon_after:
                self._zones[zone_id] = ZoneState.ABANDONED
                abandoned.append(zone_id)
        return tuple(abandoned)

    def _reopen(self, zone_id: str) -> None:
        self._zones[zone_id] = ZoneState.OPEN
        self._holder.pop(zone_id, None)


def _check_names(what: str, names: Sequence[str]) -> None:
    for index, name in enumerate(names):
        if not isinstance(name, str) or not name:
            raise ValueError(f"{what}[{index}]: must be a non-empty string, got {name!r}")
        if name in names[:index]:
            raise ValueError(f"{what}[{index}]: {name} is listed twice")
