"""The search-and-rescue app's course world: its markers over the core's obstacle world."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml
from sar_plugins.sar.course_world import (
    COURSE_WORLD,
    load_course_world,
    main,
    parse_course_world,
)

from sar_framework.sim.occupancy import DEFAULT_MAP_PREFIX
from sar_framework.sim.world import Box, Cylinder, WorldError

SHARED_SPEC_WORLD = Path("/work/shared/spec/world.yaml")


def test_course_world_facts() -> None:
    course = load_course_world()
    world = course.world
    assert world.name == "final_project" and world.source == str(COURSE_WORLD)
    assert len(world.walls) == 8
    assert [type(d) for d in world.debris] == [Box, Box, Box, Cylinder]
    names = [m.name for m in course.markers]
    assert names == ["zone_a", "zone_b", "zone_c", "zone_d", "base_station"]
    assert world.robot.spawn.x == world.robot.spawn.y == world.robot.spawn.yaw == 0.0
    assert world.robot.footprint_radius == 0.22
    assert course.marker("zone_c").survivor is True
    assert world.bounds() == pytest.approx((-6.075, -5.075, 6.075, 5.075))


@pytest.mark.skipif(not SHARED_SPEC_WORLD.exists(), reason="shared spec not mounted")
def test_same_facts_as_the_shared_spec() -> None:
    ours, spec = load_course_world(), load_course_world(SHARED_SPEC_WORLD)
    assert (ours.world.walls, ours.world.debris, ours.markers, ours.world.robot) == (
        spec.world.walls, spec.world.debris, spec.markers, spec.world.robot)


def test_unknown_marker_lists_known() -> None:
    with pytest.raises(KeyError, match="zone_a"):
        load_course_world().marker("zone_z")


@pytest.mark.parametrize(("edit", "pattern"), [
    (lambda d: d["markers"][0].update(survivor="yes"),
     r"w\.yaml: markers\[0\]\.survivor: expected"),
    (lambda d: d["markers"][1].update(name="zone_a"), r"w\.yaml: zone_a: duplicate marker"),
    (lambda d: d["markers"][2].pop("radius"), r"markers\[2\]\.radius: missing key"),
    (lambda d: d["walls"][0].pop("x"), r"walls\[0\]\.x: missing key"),
])
def test_a_malformed_course_world_names_file_and_key(edit, pattern) -> None:
    doc = yaml.safe_load(COURSE_WORLD.read_text(encoding="utf-8"))
    edit(doc)
    with pytest.raises(WorldError, match=pattern):
        parse_course_world(doc, "w.yaml")


def test_the_committed_map_is_the_course_world_rasterised(tmp_path: Path, monkeypatch) -> None:
    import sar_framework.sim.occupancy as occupancy

    monkeypatch.setattr(occupancy, "DEFAULT_MAP_PREFIX", tmp_path / DEFAULT_MAP_PREFIX.name)
    assert main([]) == 0
    for ext in (".pgm", ".yaml"):
        committed = DEFAULT_MAP_PREFIX.with_name(DEFAULT_MAP_PREFIX.name + ext).read_bytes()
        assert (tmp_path / (DEFAULT_MAP_PREFIX.name + ext)).read_bytes() == committed


def test_a_bad_course_world_file_is_an_error_not_a_traceback(tmp_path: Path, capsys) -> None:
    assert main([str(tmp_path / "nope.yaml")]) == 1
    assert "nope.yaml: cannot read world file" in capsys.readouterr().err
