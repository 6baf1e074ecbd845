"""The zone ledger and its sequential single-item auction (no ROS)."""

from __future__ import annotations

import math

import pytest
from sar_plugins.sar.fleet.auction import Award, RobotState, ZoneAuction, ZoneState

INF = math.inf


def ready(zones: list[str], robots: list[str], now: float = 0.0) -> ZoneAuction:
    auction = ZoneAuction(zones)
    for robot in robots:
        assert auction.request(robot, now).accepted
    return auction


def one_round(auction: ZoneAuction, bids: dict[str, dict[str, float]],
              now: float = 0.0) -> tuple[Award, ...]:
    notice = auction.open_round(now)
    assert notice is not None
    for robot, costs in bids.items():
        assert auction.bid(notice.auction_id, robot, costs) is None
    return auction.close_round(now).awards


def test_the_lowest_bid_wins() -> None:
    auction = ready(["a", "b"], ["r1", "r2"])
    awards = one_round(auction, {"r1": {"a": 5.0, "b": 3.0}, "r2": {"a": 4.0, "b": 1.0}})
    assert [(w.robot, w.zone_id, w.cost) for w in awards] == [("r2", "b", 1.0), ("r1", "a", 5.0)]
    assert auction.zone_state("b") is ZoneState.CLAIMED and auction.holder("b") == "r2"
    assert auction.robot_state("r1") is RobotState.BUSY


def test_one_zone_per_robot_per_round() -> None:
    auction = ready(["a", "b", "c"], ["r1"])
    awards = one_round(auction, {"r1": {"a": 1.0, "b": 2.0, "c": 3.0}})
    assert [(w.robot, w.zone_id) for w in awards] == [("r1", "a")]
    assert auction.open_zones() == ("b", "c")


def test_ties_are_broken_by_names() -> None:
    auction = ready(["a", "b"], ["r2", "r1"])
    awards = one_round(auction, {"r2": {"a": 2.0, "b": 2.0}, "r1": {"a": 2.0, "b": 2.0}})
    assert [(w.robot, w.zone_id) for w in awards] == [("r1", "a"), ("r2", "b")]


def test_the_notice_offers_open_zones_to_waiting_robots_in_mission_order() -> None:
    auction = ready(["c", "a", "b"], ["r1", "r2"])
    one_round(auction, {"r1": {"a": 1.0}, "r2": {"c": INF}})  # r1 busy with a
    notice = auction.open_round(1.0)
    assert notice is not None
    assert (notice.auction_id, notice.zone_ids, notice.bidders) == (2, ("c", "b"), ("r2",))


def test_searched_and_claimed_zones_are_never_awarded() -> None:
    auction = ready(["a", "b"], ["r1", "r2"])
    one_round(auction, {"r1": {"a": 1.0}, "r2": {"a": 2.0}})
    assert auction.finish("r1", "a", searched=True) is None
    auction.request("r1", 1.0)
    notice = auction.open_round(1.0)
    assert notice is not None and notice.zone_ids == ("b",)
    assert "not offered" in (auction.bid(notice.auction_id, "r1", {"a": 0.1}) or "")
    awards = auction.close_round(1.0).awards
    assert awards == ()
    assert auction.zone_state("a") is ZoneState.SEARCHED and auction.holder("a") == "r1"


def test_a_lost_robots_claim_reopens_and_is_awarded_again() -> None:
    auction = ZoneAuction(["a", "b"])
    auction.heard("r2", 0.0)
    auction.request("r1", 0.0)
    one_round(auction, {"r1": {"a": 1.0, "b": 2.0}})
    auction.heard("r2", 4.0)
    assert auction.expire(4.0, timeout_s=3.0) == [("r1", ("a",))]
    assert auction.robot_state("r1") is RobotState.LOST
    assert auction.zone_state("a") is ZoneState.OPEN
    assert auction.live_robots() == ("r2",)
    auction.request("r2", 4.0)
    awards = one_round(auction, {"r2": {"a": 3.0, "b": 4.0}}, now=4.0)
    assert [(w.robot, w.zone_id) for w in awards] == [("r2", "a")]
    assert auction.finish("r1", "a", searched=True) == "r1 does not hold a (it is claimed by r2)"


def test_silence_within_the_timeout_is_not_lost() -> None:
    auction = ZoneAuction(["a"])
    auction.heard("r1", 0.0)
    assert auction.expire(3.0, timeout_s=3.0) == []
    auction.heard("r1", 2.5)
    assert auction.expire(5.4, timeout_s=3.0) == []
    assert auction.expire(5.6, timeout_s=3.0) == [("r1", ())]


def test_a_lost_robot_heard_again_comes_back_idle() -> None:
    auction = ZoneAuction(["a"])
    assert auction.heard("r1", 0.0) is True
    assert auction.heard("r1", 1.0) is False
    auction.lose("r1")
    assert auction.heard("r1", 9.0) is True
    assert auction.robot_state("r1") is RobotState.IDLE


def test_a_bidder_lost_during_a_round_does_not_hold_it_open() -> None:
    auction = ready(["a"], ["r1", "r2"])
    notice = auction.open_round(0.0)
    assert notice is not None
    assert auction.bid(notice.auction_id, "r1", {"a": 9.0}) is None
    assert not auction.round_ready(0.5, window_s=2.0)
    auction.lose("r2")
    assert auction.round_ready(0.5, window_s=2.0)
    assert [w.robot for w in auction.close_round(0.5).awards] == ["r1"]


def test_the_window_closes_a_round_without_every_bid() -> None:
    auction = ready(["a"], ["r1", "r2"])
    notice = auction.open_round(0.0)
    assert notice is not None
    auction.bid(notice.auction_id, "r2", {"a": 9.0})
    assert not auction.round_ready(1.9, window_s=2.0)
    assert auction.round_ready(2.0, window_s=2.0)
    assert [w.robot for w in auction.close_round(2.0).awards] == ["r2"]
    assert auction.robot_state("r1") is RobotState.WAITING  # it bids in the next round


def test_a_given_back_zone_is_not_offered_to_that_robot_again() -> None:
    auction = ready(["a", "b"], ["r1", "r2"])
    one_round(auction, {"r1": {"a": 1.0}, "r2": {"b": 1.0}})
    assert auction.finish("r1", "a", searched=False) is None
    assert auction.zone_state("a") is ZoneState.OPEN
    auction.request("r1", 1.0)
    assert auction.open_round(1.0) is None  # r1 may not bid on a; nothing else is open
    auction.finish("r2", "b", searched=True)
    auction.request("r2", 2.0)
    notice = auction.open_round(2.0)
    assert notice is not None and notice.bidders == ("r2",) and notice.zone_ids == ("a",)
    auction.bid(notice.auction_id, "r2", {"a": 6.0})
    assert [(w.robot, w.zone_id) for w in auction.close_round(2.0).awards] == [("r2", "a")]


def test_a_given_back_bid_is_ignored() -> None:
    auction = ready(["a", "b"], ["r1", "r2"])
    one_round(auction, {"r1": {"a": 1.0}, "r2": {"b": 1.0}})
    auction.finish("r1", "a", searched=False)
    auction.finish("r2", "b", searched=True)
    auction.request("r1", 1.0)
    auction.request("r2", 1.0)
    notice = auction.open_round(1.0)
    assert notice is not None and notice.bidders == ("r2",)


def test_a_zone_every_live_robot_gave_back_is_abandoned_and_work_is_done() -> None:
    auction = ready(["a"], ["r1", "r2"])
    one_round(auction, {"r1": {"a": 1.0}})
    auction.finish("r1", "a", searched=False)
    assert auction.abandon_unreachable() == ()
    auction.request("r1", 1.0)
    auction.request("r2", 1.0)
    one_round(auction, {"r2": {"a": 2.0}}, now=1.0)
    auction.finish("r2", "a", searched=False)
    assert auction.abandon_unreachable() == ("a",)
    assert auction.zone_state("a") is ZoneState.ABANDONED
    assert auction.done()
    answer = auction.request("r1", 2.0)
    assert (answer.accepted, answer.done) == (False, True)


def test_a_lost_robot_does_not_keep_a_zone_from_being_abandoned() -> None:
    auction = ready(["a"], ["r1", "r2"])
    one_round(auction, {"r1": {"a": 1.0}})
    auction.finish("r1", "a", searched=False)
    auction.lose("r2")
    assert auction.abandon_unreachable() == ("a",)


def test_a_zone_nobody_can_reach_is_abandoned_after_rounds_in_a_row() -> None:
    auction = ready(["a", "b"], ["r1"])
    notice = auction.open_round(0.0)
    assert notice is not None
    auction.bid(notice.auction_id, "r1", {"a": INF, "b": INF})
    assert auction.close_round(0.0).abandoned == ()
    assert auction.open_round(0.5, retry_after_s=2.0) is None  # same round: wait to retry
    notice = auction.open_round(2.0, retry_after_s=2.0)
    assert notice is not None and notice.auction_id == 2
    auction.bid(notice.auction_id, "r1", {"a": INF, "b": 4.0})
    result = auction.close_round(2.0)
    assert result.abandoned == ("a",) and [w.zone_id for w in result.awards] == ["b"]


def test_a_zone_left_out_of_every_bid_is_unknown_not_unreachable() -> None:
    # A robot whose planner did not answer (busy, starting) bids nothing for a zone: that
    # is no evidence it cannot reach it, so the zone is never abandoned for it.
    auction = ready(["a", "b"], ["r1"])
    for round_number, now in enumerate((0.0, 2.0, 4.0), start=1):
        notice = auction.open_round(now, retry_after_s=2.0)
        assert notice is not None and notice.auction_id == round_number
        auction.bid(notice.auction_id, "r1", {"b": INF})
        assert "a" not in auction.close_round(now).abandoned
    assert auction.zone_state("a") is ZoneState.OPEN
    assert auction.zone_state("b") is ZoneState.ABANDONED


def test_an_inf_bid_does_not_abandon_while_another_live_robot_did_not_bid() -> None:
    auction = ZoneAuction(["a"], abandon_after_rounds=1)
    auction.heard("r2", 0.0)  # live, not asking
    auction.request("r1", 0.0)
    notice = auction.open_round(0.0)
    assert notice is not None
    auction.bid(notice.auction_id, "r1", {"a": INF})
    assert auction.close_round(0.0).abandoned == ()
    assert auction.zone_state("a") is ZoneState.OPEN


def test_done_when_every_zone_is_searched() -> None:
    auction = ready(["a", "b"], ["r1", "r2"])
    assert not auction.done()
    one_round(auction, {"r1": {"a": 1.0}, "r2": {"b": 1.0}})
    auction.finish("r1", "a", searched=True)
    assert not auction.done()
    auction.finish("r2", "b", searched=True)
    assert auction.done()
    assert auction.open_round(9.0) is None


def test_asking_again_while_holding_a_claim_gives_it_back_to_the_auction() -> None:
    auction = ready(["a"], ["r1"])
    one_round(auction, {"r1": {"a": 1.0}})
    assert auction.request("r1", 1.0).accepted
    assert auction.zone_state("a") is ZoneState.OPEN
    assert auction.robot_state("r1") is RobotState.WAITING


def test_a_repeated_bid_replaces_the_first() -> None:
    auction = ready(["a", "b"], ["r1"])
    notice = auction.open_round(0.0)
    assert notice is not None
    auction.bid(notice.auction_id, "r1", {"a": 1.0, "b": 2.0})
    auction.bid(notice.auction_id, "r1", {"a": 3.0, "b": 2.0})
    assert [w.zone_id for w in auction.close_round(0.0).awards] == ["b"]


@pytest.mark.parametrize(("auction_id", "robot", "costs", "reason"), [
    (7, "r1", {"a": 1.0}, "auction 7 is not open (auction 1 is open)"),
    (1, "r9", {"a": 1.0}, "r9 is not a bidder of auction 1 (bidders: r1)"),
    (1, "", {"a": 1.0}, "(empty name) is not a bidder of auction 1 (bidders: r1)"),
    (1, "r1", {"zz": 1.0}, "zone 'zz' is not offered in auction 1"),
    (1, "r1", {"a": math.nan}, "cost for a must be a number >= 0 or inf, got nan"),
    (1, "r1", {"a": -1.0}, "cost for a must be a number >= 0 or inf, got -1.0"),
])
def test_bad_bids_are_refused_with_a_reason(auction_id: int, robot: str,
                                            costs: dict[str, float], reason: str) -> None:
    auction = ready(["a"], ["r1"])
    assert auction.open_round(0.0) is not None
    assert auction.bid(auction_id, robot, costs) == reason


def test_a_bid_without_an_open_round_is_refused() -> None:
    assert ZoneAuction(["a"]).bid(1, "r1", {}) == "auction 1 is not open (no auction is open)"


@pytest.mark.parametrize(("robot", "zone", "reason"), [
    ("r1", "zz", "unknown zone 'zz' (zones: a, b)"),
    ("r2", "a", "r2 does not hold a (it is claimed by r1)"),
    ("r1", "b", "r1 does not hold b (it is open)"),
])
def test_bad_finishes_are_refused_with_a_reason(robot: str, zone: str, reason: str) -> None:
    auction = ready(["a", "b"], ["r1", "r2"])
    one_round(auction, {"r1": {"a": 1.0}})
    assert auction.finish(robot, zone, searched=True) == reason


def test_an_empty_robot_name_is_refused() -> None:
    answer = ZoneAuction(["a"]).request("", 0.0)
    assert (answer.accepted, answer.reason) == (False, "empty robot name")
    with pytest.raises(ValueError, match="empty robot name"):
        ZoneAuction(["a"]).heard("", 0.0)


@pytest.mark.parametrize(("zones", "message"), [
    ([], "zone_ids: empty"),
    (["a", ""], r"zone_ids\[1\]: must be a non-empty string"),
    (["a", "a"], r"zone_ids\[1\]: a is listed twice"),
])
def test_bad_zone_lists_are_refused(zones: list[str], message: str) -> None:
    with pytest.raises(ValueError, match=message):
        ZoneAuction(zones)


def test_closing_without_a_round_is_an_error() -> None:
    with pytest.raises(RuntimeError, match="no auction is open"):
        ZoneAuction(["a"]).close_round()


def test_a_robot_joining_later_reopens_the_zones_abandoned_without_it() -> None:
    auction = ready(["a", "b"], ["r1"])
    one_round(auction, {"r1": {"a": 1.0}})
    auction.finish("r1", "a", searched=False)
    assert auction.abandon_unreachable() == ("a",)
    assert auction.heard("r2", 1.0) is True
    assert auction.reopen_abandoned("r2") == ("a",)
    assert auction.zone_state("a") is ZoneState.OPEN
    auction.request("r2", 1.0)
    notice = auction.open_round(1.0)
    assert notice is not None and notice.bidders == ("r2",) and "a" in notice.zone_ids


def test_a_rejoining_robot_does_not_reopen_what_it_gave_back() -> None:
    auction = ready(["a"], ["r1"])
    one_round(auction, {"r1": {"a": 1.0}})
    auction.finish("r1", "a", searched=False)
    auction.lose("r1")
    auction.heard("r2", 1.0)
    auction.lose("r2")
    assert auction.abandon_unreachable() == ()  # no live robot: nothing is decided
    auction.heard("r1", 2.0)
    assert auction.abandon_unreachable() == ("a",)
    assert auction.reopen_abandoned("r1") == ()
    assert auction.done()


# -- the first round: the fleet starts together ---------------------------------------------


def starting(robots: tuple[str, ...] = ("r1", "r2", "r3")) -> ZoneAuction:
    return ZoneAuction(["a", "b", "c"], robots=robots, start_wait_s=10.0)


def test_the_first_round_waits_until_every_robot_of_the_fleet_asked() -> None:
    auction = starting()
    auction.request("r1", 0.0)
    assert auction.open_round(1.0) is None
    auction.request("r3", 2.0)
    assert auction.open_round(2.0) is None
    auction.request("r2", 3.0)
    notice = auction.open_round(3.0)
    assert notice is not None and notice.bidders == ("r1", "r3", "r2")


def test_without_names_the_first_round_waits_for_every_robot_heard() -> None:
    auction = starting(robots=())
    auction.heard("r2", 0.0)  # a heartbeat: it runs, it has not asked yet
    auction.request("r1", 0.0)
    assert auction.open_round(1.0) is None
    auction.request("r2", 2.0)
    notice = auction.open_round(2.0)
    assert notice is not None and notice.bidders == ("r2", "r1")  # in the order first heard


def test_the_first_round_opens_after_the_start_wait_with_the_robots_waiting() -> None:
    auction = starting()
    auction.heard("r2", 0.0)
    auction.request("r1", 1.0)  # the wait counts from the first robot asking
    assert auction.open_round(10.9) is None
    notice = auction.open_round(11.0)
    assert notice is not None and notice.bidders == ("r1",)


def test_later_rounds_do_not_wait_for_the_fleet() -> None:
    auction = starting(robots=("r1", "r2"))
    auction.request("r1", 0.0)
    auction.request("r2", 0.0)
    one_round(auction, {"r1": {"a": 1.0}, "r2": {"a": 2.0, "b": INF, "c": INF}})
    auction.heard("r3", 1.0)  # a robot nobody expected; r1 busy: only r2 asks
    notice = auction.open_round(1.0)
    assert notice is not None and notice.bidders == ("r2",)


def test_a_lost_robot_does_not_hold_the_first_round() -> None:
    auction = starting()
    for robot in ("r2", "r3"):
        auction.heard(robot, 0.0)
    auction.request("r1", 0.0)
    auction.lose("r2")
    auction.lose("r3")
    notice = auction.open_round(1.0)
    assert notice is not None and notice.bidders == ("r1",)


@pytest.mark.parametrize(("options", "message"), [
    ({"robots": ["r1", ""]}, r"robots\[1\]: must be a non-empty string"),
    ({"robots": ["r1", "r1"]}, r"robots\[1\]: r1 is listed twice"),
    ({"start_wait_s": -1.0}, "start_wait_s must be >= 0, got -1.0"),
])
def test_bad_start_settings_are_refused(options: dict, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        ZoneAuction(["a"], **options)
