"""A world as obstacle geometry: walls, debris and the robot, from a YAML data file.

A world file describes a Gazebo-like world in the ``map`` frame: walls and debris (oriented
boxes and cylinders) and the robot (spawn pose, footprint radius). :func:`load_world` turns
it into frozen dataclasses; every problem raises :class:`WorldError` naming the file and the
key, e.g. ``w.yaml: walls[2].size: expected [length, width] ...``. The simulator itself
runs on a map (:mod:`.occupancy`); a world is what :mod:`.map_writer` rasterises into one.
An app's own sections of a world file (what its floor marks mean) are read by the app:
``sections`` names them, and the core leaves them alone.
"""

from __future__ import annotations

import math
from collections.abc import Collection, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml


class WorldError(ValueError):
    """A world file is missing, unreadable or malformed; the message names file and key."""


@dataclass(frozen=True)
class Pose2D:
    """A planar pose in the ``map`` frame.

    Attributes:
        x: Metres.
        y: Metres.
        yaw: Radians, counter-clockwise from +x.
    """

    x: float
    y: float
    yaw: float = 0.0


@dataclass(frozen=True)
class Box:
    """An oriented box obstacle (a wall or a piece of debris).

    Attributes:
        name: Unique name in the world.
        x: Centre x, metres.
        y: Centre y, metres.
        length: Size along the box's own x axis, metres.
        width: Size along the box's own y axis, metres.
        yaw: Rotation of the box's x axis from the map's x axis, radians.
    """

    name: str
    x: float
    y: float
    length: float
    width: float
    yaw: float = 0.0

    def corners(self) -> list[tuple[float, float]]:
        """Return the four corners counter-clockwise, starting at the box's (-x, -y) corner."""
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        hl, hw = self.length / 2.0, self.width / 2.0
        return [
            (self.x + c * u - s * v, self.y + s * u + c * v)
            for u, v in ((-hl, -hw), (hl, -hw), (hl, hw), (-hl, hw))
        ]

    def bounds(self) -> tuple[float, float, float, float]:
        """Return the axis-aligned bounding box ``(min_x, min_y, max_x, max_y)``."""
        corners = self.corners()
        xs = [c[0] for c in corners]
        ys = [c[1] for c in corners]
        return min(xs), min(ys), max(xs), max(ys)


@dataclass(frozen=True)
class Cylinder:
    """A cylindrical obstacle.

    Attributes:
        name: Unique name in the world.
        x: Centre x, metres.
        y: Centre y, metres.
        radius: Metres.
    """

    name: str
    x: float
    y: float
    radius: float

    def bounds(self) -> tuple[float, float, float, float]:
        """Return the axis-aligned bounding box ``(min_x, min_y, max_x, max_y)``."""
        r = self.radius
        return self.x - r, self.y - r, self.x + r, self.y + r


Obstacle = Box | Cylinder


@dataclass(frozen=True)
class Robot:
    """The simulated robot.

    Attributes:
        name: Model name.
        spawn: Where the robot starts.
        footprint_radius: Circumscribed footprint radius, metres (Nav2's ``robot_radius``).
    """

    name: str
    spawn: Pose2D
    footprint_radius: float


@dataclass(frozen=True)
class World:
    """A loaded world.

    Attributes:
        name: World name.
        walls: Wall boxes.
        debris: Debris boxes and cylinders.
        robot: The robot description.
        source: The file the world came from (for messages).
    """

    name: str
    walls: tuple[Box, ...]
    debris: tuple[Obstacle, ...]
    robot: Robot
    source: str = "<memory>"

    @property
    def obstacles(self) -> tuple[Obstacle, ...]:
        """Every obstacle that blocks the robot: walls, then debris."""
        return self.walls + self.debris

    def bounds(self) -> tuple[float, float, float, float]:
        """Return the bounding box ``(min_x, min_y, max_x, max_y)`` of every obstacle."""
        boxes = [o.bounds() for o in self.obstacles]
        return (
            min(b[0] for b in boxes),
            min(b[1] for b in boxes),
            max(b[2] for b in boxes),
            max(b[3] for b in boxes),
        )



class WorldReader:
    """Typed access to a parsed YAML document that reports errors as ``file: key: problem``.

    Args:
        source: The file name used in error messages.
    """

    def __init__(self, source: str) -> None:
        self.source = source

    def fail(self, key: str, problem: str) -> WorldError:
        """The error for ``key``: ``file: key: problem``."""
        return WorldError(f"{self.source}: {key}: {problem}")

    def mapping(self, value: Any, key: str, allowed: set[str]) -> Mapping[str, Any]:
        """``value`` as a mapping whose keys are all ``allowed``."""
        if not isinstance(value, Mapping):
            raise self.fail(key, f"expected a mapping, got {value!r}")
        unknown = sorted(set(value) - allowed, key=str)
        if unknown:
            raise self.fail(
                f"{key}.{unknown[0]}", f"unknown key (allowed: {', '.join(sorted(allowed))})"
            )
        return value

    def field(self, entry: Mapping[str, Any], parent: str, name: str) -> Any:
        """``entry[name]``, a required key."""
        if name not in entry:
            raise self.fail(f"{parent}.{name}", "missing key")
        return entry[name]

    def number(self, value: Any, key: str, *, positive: bool = False) -> float:
        """``value`` as a finite number (positive if asked)."""
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self.fail(key, f"expected a number, got {value!r}")
        number = float(value)
        if not math.isfinite(number):
            raise self.fail(key, f"expected a finite number, got {value!r}")
        if positive and number <= 0.0:
            raise self.fail(key, f"expected a positive number, got {value!r}")
        return number

    def num_field(
        self, entry: Mapping[str, Any], parent: str, name: str, *, positive: bool = False
    ) -> float:
        """``entry[name]`` as a finite number (positive if asked)."""
        return self.number(self.field(entry, parent, name), f"{parent}.{name}", positive=positive)

    def text(self, value: Any, key: str) -> str:
        """``value`` as a non-empty string."""
        if not isinstance(value, str) or not value:
            raise self.fail(key, f"expected a non-empty string, got {value!r}")
        return value

    def items(self, doc: Mapping[str, Any], key: str) -> list[Any]:
        """``doc[key]`` as a list (none: [])."""
        value = doc.get(key, [])
        if value is None:
            return []
        if not isinstance(value, list):
            raise self.fail(key, f"expected a list, got {type(value).__name__}")
        return value


_BOX_KEYS = {"name", "shape", "x", "y", "size", "yaw"}
_CYLINDER_KEYS = {"name", "shape", "x", "y", "radius"}


def _box(r: WorldReader, entry: Mapping[str, Any], key: str) -> Box:
    r.mapping(entry, key, _BOX_KEYS)
    size = r.field(entry, key, "size")
    if not isinstance(size, list) or len(size) != 2:
        raise r.fail(f"{key}.size", f"expected [length, width], got {size!r}")
    return Box(
        name=r.text(r.field(entry, key, "name"), f"{key}.name"),
        x=r.num_field(entry, key, "x"),
        y=r.num_field(entry, key, "y"),
        length=r.number(size[0], f"{key}.size[0]", positive=True),
        width=r.number(size[1], f"{key}.size[1]", positive=True),
        yaw=r.number(entry.get("yaw", 0.0), f"{key}.yaw"),
    )


def _obstacle(r: WorldReader, entry: Any, key: str) -> Obstacle:
    shape = entry.get("shape", "box") if isinstance(entry, Mapping) else "box"
    if shape == "box":
        return _box(r, entry, key)
    if shape == "cylinder":
        r.mapping(entry, key, _CYLINDER_KEYS)
        return Cylinder(
            name=r.text(r.field(entry, key, "name"), f"{key}.name"),
            x=r.num_field(entry, key, "x"),
            y=r.num_field(entry, key, "y"),
            radius=r.num_field(entry, key, "radius", positive=True),
        )
    raise r.fail(f"{key}.shape", f"expected 'box' or 'cylinder', got {shape!r}")


def _robot(r: WorldReader, value: Any) -> Robot:
    entry = r.mapping(value, "robot", {"name", "spawn", "footprint_radius"})
    spawn = r.mapping(r.field(entry, "robot", "spawn"), "robot.spawn", {"x", "y", "yaw"})
    return Robot(
        name=r.text(entry.get("name", "robot"), "robot.name"),
        spawn=Pose2D(
            x=r.num_field(spawn, "robot.spawn", "x"),
            y=r.num_field(spawn, "robot.spawn", "y"),
            yaw=r.number(spawn.get("yaw", 0.0), "robot.spawn.yaw"),
        ),
        footprint_radius=r.num_field(entry, "robot", "footprint_radius", positive=True),
    )


def parse_world(doc: Any, source: str = "<memory>", *, sections: Collection[str] = ()) -> World:
    """Build a :class:`World` from an already parsed YAML document.

    Args:
        doc: The document (a mapping with ``world``, ``walls``, ``debris``, ``robot``).
        source: The file name used in error messages.
        sections: Top-level keys an app reads itself; allowed here, and left alone.

    Returns:
        The world.

    Raises:
        WorldError: If a key is missing, unknown, of the wrong type, or a name repeats.
    """
    r = WorldReader(source)
    if not isinstance(doc, Mapping):
        raise WorldError(f"{source}: expected a mapping at the top level, got {doc!r}")
    r.mapping(doc, "<top level>", {"world", "walls", "debris", "robot", *sections})
    walls = tuple(_box(r, e, f"walls[{i}]") for i, e in enumerate(r.items(doc, "walls")))
    debris = tuple(_obstacle(r, e, f"debris[{i}]") for i, e in enumerate(r.items(doc, "debris")))
    if not walls and not debris:
        raise r.fail("walls", "a world needs at least one obstacle")
    seen: set[str] = set()
    for item in walls + debris:
        if item.name in seen:
            raise r.fail(f"{item.name}", "duplicate obstacle name")
        seen.add(item.name)
    return World(
        name=r.text(doc.get("world", Path(source).stem), "world"),
        walls=walls,
        debris=debris,
        robot=_robot(r, r.field(doc, "<top level>", "robot")),
        source=source,
    )


def read_world_file(path: str | Path) -> Any:
    """The parsed YAML document of a world file.

    Raises:
        WorldError: If the file cannot be read or is not valid YAML.
    """
    source = str(path)
    try:
        text = Path(path).read_text(encoding="utf-8")
    except OSError as exc:
        raise WorldError(f"{source}: cannot read world file: {exc.strerror or exc}") from exc
    try:
        return yaml.safe_load(text)
    except yaml.YAMLError as exc:
        raise WorldError(f"{source}: invalid YAML: {exc}") from exc


def load_world(path: str | Path, *, sections: Collection[str] = ()) -> World:
    """Load a world file.

    Args:
        path: The YAML file.
        sections: Top-level keys an app reads itself (:func:`parse_world`).

    Returns:
        The world; ``World.source`` is ``path`` as given.

    Raises:
        WorldError: If the file cannot be read, is not valid YAML, or is malformed.
    """
    return parse_world(read_world_file(path), str(path), sections=sections)
