"""World file loading: obstacles and robot, errors that name file and key, apps' sections."""

import math

import pytest
import yaml

from sar_framework.sim.world import (
    Box,
    Cylinder,
    WorldError,
    load_world,
    parse_world,
)

ROOM = """\
world: room
walls:
  - {name: north, x: 0.0, y: 2.0, size: [4.0, 0.1]}
  - {name: south, x: 0.0, y: -2.0, size: [4.0, 0.1]}
  - {name: east, x: 2.0, y: 0.0, size: [0.1, 4.1], yaw: 0.0}
debris:
  - {name: drum, shape: cylinder, x: 1.0, y: 1.0, radius: 0.2}
robot:
  name: bot
  spawn: {x: -1.0, y: 0.0, yaw: 1.5}
  footprint_radius: 0.2
"""


def world_doc() -> dict:
    return yaml.safe_load(ROOM)


def test_a_world_file_gives_obstacles_and_robot(tmp_path):
    path = tmp_path / "room.yaml"
    path.write_text(ROOM)
    world = load_world(path)
    assert world.name == "room" and world.source == str(path)
    assert [w.name for w in world.walls] == ["north", "south", "east"]
    assert [type(d) for d in world.debris] == [Cylinder]
    assert (world.robot.spawn.x, world.robot.spawn.yaw, world.robot.footprint_radius) == (
        -1.0, 1.5, 0.2)
    assert world.bounds() == pytest.approx((-2.0, -2.05, 2.05, 2.05))


def test_an_apps_sections_are_allowed_only_when_named():
    doc = {**world_doc(), "markers": [{"name": "m", "x": 0}]}
    with pytest.raises(WorldError, match=r"<top level>\.markers: unknown key"):
        parse_world(doc, "w.yaml")
    assert parse_world(doc, "w.yaml", sections=("markers",)).name == "room"


def test_box_corners_follow_yaw():
    box = Box("b", x=1.0, y=2.0, length=2.0, width=1.0, yaw=math.pi / 2)
    corners = box.corners()
    assert corners[0] == pytest.approx((1.5, 1.0))
    assert corners[2] == pytest.approx((0.5, 3.0))
    assert box.bounds() == pytest.approx((0.5, 1.0, 1.5, 3.0))


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
        (lambda d: d["debris"][0].update(shape="cone"), r"debris\[0\]\.shape: expected 'box' or"),
        (lambda d: d["debris"][0].pop("radius"), r"debris\[0\]\.radius: missing key"),
        (lambda d: d["debris"][0].update(name="north"), r"north: duplicate obstacle"),
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
