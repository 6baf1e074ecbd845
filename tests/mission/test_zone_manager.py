"""ZoneManager: the spec's API, input validation, copies, and property tests."""

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st
from sar_plugins.sar.zone_manager import ZoneManager
from sar_testing.leaf_harness import BASE, SPEC_ZONES


def make() -> ZoneManager:
    return ZoneManager(SPEC_ZONES, BASE)


def test_walks_spec_zones_in_order():
    zm = make()
    assert zm.total_zones() == 4
    seen = []
    while zm.has_remaining():
        assert zm.current_index() == len(seen)
        seen.append(zm.current_zone())
        zm.advance()
    assert seen == SPEC_ZONES
    assert zm.current_index() == 4
    assert not zm.has_remaining()


def test_zones_passed_without_being_reached_are_skipped():
    """Regression: 'All zones visited' was said although a zone had been skipped."""
    zm = make()
    for reached in (True, False, True):
        if reached:
            zm.mark_reached(zm.current_zone()["id"])
        zm.advance()
    assert zm.skipped_zones() == ["zone_b"]  # zone_d is not passed yet


def test_current_zone_past_end_raises_clear_index_error():
    zm = make()
    for _ in range(4):
        zm.advance()
    with pytest.raises(IndexError, match="all 4 zones have been visited"):
        zm.current_zone()


def test_advance_is_noop_when_exhausted():
    zm = make()
    for _ in range(10):
        zm.advance()
    assert zm.current_index() == 4
    assert not zm.has_remaining()


def test_base_pose_and_zone_are_copies():
    zm = make()
    zm.base_pose()["x"] = 99.0
    zm.current_zone()["x"] = 99.0
    assert zm.base_pose() == BASE
    assert zm.current_zone() == SPEC_ZONES[0]


def test_constructor_does_not_alias_input():
    zones = [dict(z) for z in SPEC_ZONES]
    base = dict(BASE)
    zm = ZoneManager(zones, base)
    zones[0]["x"] = 42.0
    base["y"] = 42.0
    assert zm.current_zone()["x"] == -3.0
    assert zm.base_pose()["y"] == 0.0


def test_survivor_ids_count_up_independently_of_zones():
    zm = make()
    assert zm.next_survivor_id() == "survivor_1"
    zm.advance()
    assert zm.next_survivor_id() == "survivor_2"
    assert zm.next_survivor_id() == "survivor_3"


def test_ints_accepted_as_floats():
    zm = ZoneManager([{"id": "z", "x": 1, "y": 2, "yaw": 0}], {"x": 0, "y": 0, "yaw": 0})
    zone = zm.current_zone()
    assert zone == {"id": "z", "x": 1.0, "y": 2.0, "yaw": 0.0}
    assert all(isinstance(zone[k], float) for k in ("x", "y", "yaw"))


def test_empty_zone_list_is_allowed():
    zm = ZoneManager([], BASE)
    assert not zm.has_remaining()
    assert zm.total_zones() == 0
    with pytest.raises(IndexError):
        zm.current_zone()


@pytest.mark.parametrize(
    ("zone", "pattern"),
    [
        ({"x": 0.0, "y": 0.0, "yaw": 0.0}, r"zones\[0\]: key 'id'"),
        ({"id": "", "x": 0.0, "y": 0.0, "yaw": 0.0}, r"zones\[0\]: key 'id'"),
        ({"id": 3, "x": 0.0, "y": 0.0, "yaw": 0.0}, r"zones\[0\]: key 'id'"),
        ({"id": "zone_a", "y": 0.0, "yaw": 0.0}, r"zones\[0\] \('zone_a'\): missing key 'x'"),
        ({"id": "zone_a", "x": "1", "y": 0.0, "yaw": 0.0}, r"'zone_a'.*key 'x' must be a number"),
        ({"id": "zone_a", "x": True, "y": 0.0, "yaw": 0.0}, r"'zone_a'.*key 'x' must be a number"),
        ({"id": "zone_a", "x": 0.0, "y": math.nan, "yaw": 0.0}, r"key 'y' must be finite"),
        ({"id": "zone_a", "x": 0.0, "y": 0.0, "yaw": math.inf}, r"key 'yaw' must be finite"),
        ("zone_a", r"zones\[0\]: expected a mapping"),
    ],
)
def test_bad_zone_names_zone_and_key(zone, pattern):
    with pytest.raises(ValueError, match=pattern):
        ZoneManager([zone], BASE)


def test_duplicate_ids_rejected():
    zones = [SPEC_ZONES[0], SPEC_ZONES[1], dict(SPEC_ZONES[0])]
    pattern = r"zones\[2\] \('zone_a'\): key 'id' duplicates zones\[0\]"
    with pytest.raises(ValueError, match=pattern):
        ZoneManager(zones, BASE)


@pytest.mark.parametrize(
    ("base", "pattern"),
    [
        ({"x": 0.0, "y": 0.0}, "base_station: missing key 'yaw'"),
        ({"x": None, "y": 0.0, "yaw": 0.0}, "base_station: key 'x' must be a number"),
        ([0.0, 0.0, 0.0], "base_station: expected a mapping"),
    ],
)
def test_bad_base_station(base, pattern):
    with pytest.raises(ValueError, match=pattern):
        ZoneManager(SPEC_ZONES, base)


def test_zones_must_be_a_list():
    with pytest.raises(ValueError, match="zones: expected a list"):
        ZoneManager("zone_a", BASE)


finite = st.floats(allow_nan=False, allow_infinity=False, min_value=-1e6, max_value=1e6)
zone_lists = st.lists(
    st.fixed_dictionaries({"x": finite, "y": finite, "yaw": finite}), max_size=12
).map(lambda zs: [{"id": f"zone_{i}", **z} for i, z in enumerate(zs)])


@given(zones=zone_lists, advances=st.integers(min_value=0, max_value=30))
def test_property_index_bounded_and_consistent(zones, advances):
    zm = ZoneManager(zones, BASE)
    for _ in range(advances):
        zm.advance()
    expected = min(advances, len(zones))
    assert zm.current_index() == expected
    assert zm.total_zones() == len(zones)
    assert zm.has_remaining() == (expected < len(zones))
    if zm.has_remaining():
        assert zm.current_zone() == zones[expected]
    else:
        with pytest.raises(IndexError):
            zm.current_zone()


@given(zones=zone_lists)
def test_property_full_walk_visits_every_zone_once_in_order(zones):
    zm = ZoneManager(zones, BASE)
    visited = []
    while zm.has_remaining():
        visited.append(zm.current_zone()["id"])
        zm.advance()
    assert visited == [z["id"] for z in zones]


@given(n=st.integers(min_value=1, max_value=50))
def test_property_survivor_ids_unique_and_sequential(n):
    zm = make()
    ids = [zm.next_survivor_id() for _ in range(n)]
    assert ids == [f"survivor_{i}" for i in range(1, n + 1)]


@given(zones=zone_lists, data=st.data())
def test_property_duplicate_id_always_rejected(zones, data):
    if not zones:
        return
    dup = dict(data.draw(st.sampled_from(zones)))
    with pytest.raises(ValueError, match="duplicates"):
        ZoneManager([*zones, dup], BASE)


def _fleet_manager() -> ZoneManager:
    zones = [{"id": z, "x": float(i), "y": 0.0, "yaw": 0.0} for i, z in enumerate("abcd")]
    return ZoneManager(zones, {"x": 0.0, "y": 0.0, "yaw": 0.0})


def test_claim_makes_a_later_zone_current_and_keeps_the_others_in_order() -> None:
    zm = _fleet_manager()
    zm.claim("c")
    assert zm.current_zone()["id"] == "c" and zm.current_index() == 0
    zm.advance()
    assert [zm.current_zone()["id"], zm.total_zones()] == ["a", 4]
    zm.claim("d")
    zm.mark_reached("d")
    zm.advance()
    assert zm.current_zone()["id"] == "a"
    assert zm.skipped_zones() == ["c"]


def test_claim_brings_back_a_zone_already_passed() -> None:
    zm = _fleet_manager()
    zm.claim("b")
    zm.advance()  # b passed unreached (given back)
    zm.claim("a")
    zm.advance()
    zm.claim("b")  # another round gives it to this robot again
    assert zm.current_zone()["id"] == "b" and zm.current_index() == 1
    zm.mark_reached("b")
    zm.advance()
    assert zm.skipped_zones() == ["a"]
    assert zm.has_remaining()


def test_claim_of_an_unknown_zone_names_the_zones() -> None:
    expected = r"claim\(.zz.\): not a zone of the mission \(zones: a, b, c, d\)"
    with pytest.raises(KeyError, match=expected):
        _fleet_manager().claim("zz")
