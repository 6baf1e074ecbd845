"""The fleet's survivor registry (no ROS): one id per survivor, one reporter, nothing lost."""

from __future__ import annotations

import math

import pytest
from sar_plugins.sar.fleet.survivor_registry import RegistrationError, SurvivorRegistry


@pytest.fixture
def registry() -> SurvivorRegistry:
    return SurvivorRegistry(radius_m=1.0)


def test_the_first_finder_gets_survivor_1_and_reports_it(registry: SurvivorRegistry) -> None:
    answer = registry.register("robot1", 1.5, -2.0, zone_id="zone_a")
    assert (answer.survivor_id, answer.report, answer.found_by, answer.reason) == \
        ("survivor_1", True, "robot1", "")
    assert answer.first and not answer.takeover
    assert answer.zone_id == "zone_a"
    assert answer.describe() == "robot1 found survivor_1 at (1.50, -2.00): first, it reports it"


def test_a_second_finder_within_the_radius_gets_the_same_id_and_does_not_report(
        registry: SurvivorRegistry) -> None:
    registry.register("robot1", 1.5, -2.0)
    answer = registry.register("robot2", 2.2, -2.5)  # 0.86 m away
    assert (answer.survivor_id, answer.report, answer.found_by) == ("survivor_1", False, "robot1")
    assert answer.reason == "survivor_1 was registered first by robot1, which reports it"
    assert not answer.first
    assert answer.describe().startswith("robot2 found survivor_1 at (2.20, -2.50): repeat, not")
    assert len(registry) == 1


def test_the_radius_is_inclusive_and_beyond_it_is_another_survivor(
        registry: SurvivorRegistry) -> None:
    registry.register("robot1", 0.0, 0.0)
    assert registry.register("robot2", 1.0, 0.0).survivor_id == "survivor_1"
    beyond = registry.register("robot2", 1.0001, 0.0)
    assert (beyond.survivor_id, beyond.report, beyond.first) == ("survivor_2", True, True)


def test_ids_count_fleet_wide_in_registration_order(registry: SurvivorRegistry) -> None:
    ids = [registry.register(robot, x, 0.0).survivor_id
           for robot, x in (("robot1", 0.0), ("robot2", 5.0), ("robot1", 10.0), ("robot3", 5.3))]
    assert ids == ["survivor_1", "survivor_2", "survivor_3", "survivor_2"]
    assert registry.survivor_ids() == ("survivor_1", "survivor_2", "survivor_3")


def test_the_nearest_known_survivor_wins_and_positions_do_not_drift(
        registry: SurvivorRegistry) -> None:
    registry.register("robot1", 0.0, 0.0)
    registry.register("robot1", 1.8, 0.0)  # survivor_2: 1.8 m from survivor_1
    assert registry.register("robot2", 1.1, 0.0).survivor_id == "survivor_2"  # 0.7 vs 1.1
    # matching is against the first position, so a chain of finds does not walk an id away
    registry.register("robot2", 2.7, 0.0)
    assert registry.register("robot3", 3.5, 0.0).survivor_id == "survivor_3"
    assert registry.position_of("survivor_2") == (1.8, 0.0)


def test_the_reporter_asking_again_gets_the_same_answer(registry: SurvivorRegistry) -> None:
    first = registry.register("robot1", 1.5, -2.0)
    again = registry.register("robot1", 1.6, -2.0)  # a request sent again, a retried branch
    assert (again.survivor_id, again.report, again.reason) == ("survivor_1", True, "")
    assert not again.first and first.first
    registry.mark_reported("survivor_1")
    assert registry.register("robot1", 1.5, -2.0).report, "still the reporter, once reported"


def test_a_lost_reporter_hands_its_unreported_survivor_to_the_next_finder(
        registry: SurvivorRegistry) -> None:
    registry.register("robot1", 1.5, -2.0)
    registry.register("robot2", 1.5, -2.1)  # not the reporter
    assert registry.robot_lost("robot1") == ("survivor_1",)
    assert registry.reporter_of("survivor_1") is None
    taken = registry.register("robot3", 1.4, -2.0)
    assert (taken.survivor_id, taken.report, taken.found_by, taken.takeover) == \
        ("survivor_1", True, "robot1", True)
    assert taken.describe().endswith("repeat, it reports it (its reporter was lost)")
    later = registry.register("robot2", 1.5, -2.0)
    assert not later.report
    assert later.reason == ("survivor_1 was registered first by robot1; robot3 reports it "
                            "(took it over from a lost robot)")


def test_a_reported_survivor_is_not_handed_back_when_its_reporter_is_lost(
        registry: SurvivorRegistry) -> None:
    registry.register("robot1", 1.5, -2.0)
    registry.mark_reported("survivor_1")
    assert registry.robot_lost("robot1") == ()
    answer = registry.register("robot2", 1.5, -2.0)
    assert not answer.report
    assert answer.reason == "survivor_1 was already reported by robot1"


def test_a_survivor_reported_while_handed_back_is_not_taken_over(
        registry: SurvivorRegistry) -> None:
    registry.register("robot1", 1.5, -2.0)
    registry.robot_lost("robot1")
    registry.mark_reported("survivor_1")  # robot1's report reached the base after all
    answer = registry.register("robot2", 1.5, -2.0)
    assert (answer.report, answer.takeover) == (False, False)


def test_losing_a_robot_touches_only_its_own_survivors(registry: SurvivorRegistry) -> None:
    registry.register("robot1", 0.0, 0.0)
    registry.register("robot2", 5.0, 0.0)
    registry.register("robot1", 10.0, 0.0)
    assert registry.robot_lost("robot1") == ("survivor_1", "survivor_3")
    assert registry.robot_lost("robot1") == ()
    assert registry.robot_lost("nobody") == ()
    assert registry.reporter_of("survivor_2") == "robot2"


def test_a_lost_robot_that_comes_back_may_report_its_handed_back_survivor(
        registry: SurvivorRegistry) -> None:
    registry.register("robot1", 0.0, 0.0)
    registry.robot_lost("robot1")
    assert registry.register("robot1", 0.0, 0.0).report


@pytest.mark.parametrize(("x", "y", "field"), [
    (math.nan, 0.0, "x"), (0.0, math.inf, "y"), (-math.inf, 0.0, "x"), ("1.0", 0.0, "x"),
    (True, 0.0, "x"), (0.0, None, "y"),
])
def test_a_position_that_is_not_finite_is_refused_naming_the_field(
        registry: SurvivorRegistry, x: object, y: object, field: str) -> None:
    with pytest.raises(RegistrationError, match=f"^{field}: must be a finite number"):
        registry.register("robot1", x, y)  # type: ignore[arg-type]
    assert len(registry) == 0


@pytest.mark.parametrize(("robot", "message"), [
    ("", "robot: must be a non-empty name, got ''"),
    (None, "robot: must be a non-empty name, got None"),
    ("robot 1", "robot: 'robot 1' holds whitespace or control characters"),
    ("robot\n", "robot: 'robot\\\\n' holds whitespace or control characters"),
])
def test_a_bad_robot_name_is_refused(registry: SurvivorRegistry, robot: object,
                                     message: str) -> None:
    with pytest.raises(RegistrationError, match=f"^{message}$".replace("(", r"\(")):
        registry.register(robot, 0.0, 0.0)  # type: ignore[arg-type]
    assert len(registry) == 0


@pytest.mark.parametrize("radius", [0.0, -1.0, math.nan, math.inf, True, "1"])
def test_a_bad_radius_is_refused(radius: object) -> None:
    with pytest.raises(ValueError, match="radius_m must be a finite positive number"):
        SurvivorRegistry(radius)  # type: ignore[arg-type]


def test_unknown_ids_are_a_key_error(registry: SurvivorRegistry) -> None:
    with pytest.raises(KeyError, match="survivor_9"):
        registry.mark_reported("survivor_9")
    with pytest.raises(KeyError):
        registry.reporter_of("survivor_1")
