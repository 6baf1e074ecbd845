"""World file loading: the course world's facts and errors that name file and key."""

import math
from pathlib import Path

import pytest
import yaml

from sar_framework.sim.world import (
    DEFAULT_WORLD_PATH,
    Box,
    Cylinder,
    WorldError,
    load_world,
    parse_world,
)

SHARED_SPEC_WORLD = Path("/work/shared/spec/world.yaml")


def world_doc() -> dict:
    return yaml.safe_load(DEFAULT_WORLD_PATH.read_text())


def test_course_world_facts():
    world = load_world()
    assert world.name == "final_project"
    assert len(world.walls) == 8
    assert [type(d) for d in world.debris] == [Box, Box, Box, Cylinder]
    names = [m.name for m in world.markers]
    assert names == ["zone_a", "zone_b", "zone_c", "zone_d", "base_station"]
    assert world.robot.spawn.x == world.robot.spawn.y == world.robot.spawn.yaw == 0.0
    assert world.robot.footprint_radius == 0.22
    assert world.marker("zone_c").survivor is True
    assert world.bounds() == pytest.approx((-6.075, -5.075, 6.075, 5.075))
    assert world.source == str(DEFAULT_WORLD_PATH)


@pytest.mark.skipif(not SHARED_SPEC_WORLD.exists(), reason="shared spec not mounted")
def test_same_facts_as_the_shared_spec():
    ours = load_world()
    spec = load_world(SHARED_SPEC_WORLD)
    assert (ours.walls, ours.debris, ours.markers, ours.robot) == (
        spec.walls,
        spec.debris,
        spec.markers,
        spec.robot,
    )


def test_box_corners_follow_yaw():
    box = Box("b", x=1.0, y=2.0, length=2.0, width=1.0, yaw=math.pi / 2)
    corners = box.corners()
    assert corners[0] == pytest.approx((1.5, 1.0))
    assert corners[2] == pytest.approx((0.5, 3.0))
    assert box.bounds() == pytest.approx((0.5, 1.0, 1.5, 3.0))


def test_unknown_marker_lists_known():
    with pytest.raises(KeyError, match="zone_a"):
        load_world().marker("zone_z")


def test_missing_file_names_it(tmp_path):
    path = tmp_path / "nope.yaml"
    with pytest.raises(WorldError, match=r"nope\.yaml: cannot read world file"):
        load_world(path)


def test_invalid_yaml_names_file(tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text("walls: [\n")
    with pytest.raises(WorldError, match=r"bad\.yaml: invalid YAML"):
        load_world(path)


def mutate(edit) -> dict:
    doc = world_doc()
    edit(doc)
    return doc


@pytest.mark.parametrize(
    ("edit", "pattern"),
    [
        (lambda d: d["walls"][2].update(size=[1.0]), r"w\.yaml: walls\[2\]\.size: expected \["),
        (lambda d: d["walls"][2].update(size=[1.0, -1]), r"walls\[2\]\.size\[1\]: expected a pos"),
        (lambda d: d["walls"][0].pop("x"), r"walls\[0\]\.x: missing key"),
        (lambda d: d["walls"][0].update(y="north"), r"walls\[0\]\.y: expected a number"),
        (lambda d: d["walls"][0].update(yaw=float("nan")), r"walls\[0\]\.yaw: expected a finite"),
        (lambda d: d["walls"][1].update(colour="red"), r"walls\[1\]\.colour: unknown key"),
        (lambda d: d["debris"][3].update(shape="cone"), r"debris\[3\]\.shape: expected 'box' or"),
        (lambda d: d["debris"][3].pop("radius"), r"debris\[3\]\.radius: missing key"),
        (lambda d: d["debris"][0].update(name="wall_north"), r"wall_north: duplicate obstacle"),
        (lambda d: d["markers"][0].update(survivor="yes"), r"markers\[0\]\.survivor: expected"),
        (lambda d: d["robot"].pop("footprint_radius"), r"robot\.footprint_radius: missing key"),
        (lambda d: d["robot"]["spawn"].update(x=None), r"robot\.spawn\.x: expected a number"),
        (lambda d: d.pop("robot"), r"<top level>\.robot: missing key"),
        (lambda d: d.update(wals=[]), r"<top level>\.wals: unknown key"),
        (lambda d: d.update(walls={"a": 1}), r"w\.yaml: walls: expected a list"),
    ],
)
def test_malformed_world_names_file_and_key(edit, pattern):
    with pytest.raises(WorldError, match=pattern):
        parse_world(mutate(edit), "maps/w.yaml")


def test_world_without_obstacles_rejected():
    doc = mutate(lambda d: (d.update(walls=[]), d.update(debris=[])))
    with pytest.raises(WorldError, match="at least one obstacle"):
        parse_world(doc, "w.yaml")


def test_top_level_must_be_mapping():
    with pytest.raises(WorldError, match=r"w\.yaml: expected a mapping"):
        parse_world([1, 2], "w.yaml")
