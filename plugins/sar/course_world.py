"""The course's world: its obstacles, its floor markers (zones, base station) and the robot.

``maps/final_project_world.yaml`` describes the course's Gazebo world ``final_project`` in
the shared spec's format. The core reads its obstacles and robot
(:func:`sar_framework.sim.world.parse_world`); this app reads the ``markers`` section: the
visual zone disks, each with the room it lies in and whether the course places a survivor
there, and the base station. The simulator runs on the map rasterised from it
(``maps/final_project_map``), regenerated after an edit with::

    python -m sar_plugins.sar.course_world
"""

from __future__ import annotations

import sys
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from sar_framework.sim.world import World, WorldError, WorldReader, parse_world, read_world_file

COURSE_WORLD = Path(__file__).resolve().parents[2] / "maps" / "final_project_world.yaml"
"""The course world shipped with the project."""
MARKERS = "markers"
"""The world file's section this app reads."""
_MARKER_KEYS = {"name", "x", "y", "radius", "room", "colour", "survivor"}


@dataclass(frozen=True)
class Marker:
    """A floor marker (visual only, never an obstacle): a zone or the base station.

    Attributes:
        name: Unique marker name (``zone_a``, ``base_station``...).
        x: Centre x, metres.
        y: Centre y, metres.
        radius: Disk radius, metres.
        room: Optional room label (``NW``...).
        colour: Optional display colour name.
        survivor: Whether the course places a survivor here (None when not stated).
    """

    name: str
    x: float
    y: float
    radius: float
    room: str | None = None
    colour: str | None = None
    survivor: bool | None = None


@dataclass(frozen=True)
class CourseWorld:
    """The course world: the core's obstacle world and this app's markers.

    Attributes:
        world: Walls, debris and the robot.
        markers: The floor markers, in file order.
    """

    world: World
    markers: tuple[Marker, ...]

    def marker(self, name: str) -> Marker:
        """Return the marker called ``name``.

        Raises:
            KeyError: If there is none; the message lists the known markers.
        """
        for marker in self.markers:
            if marker.name == name:
                return marker
        known = ", ".join(m.name for m in self.markers)
        raise KeyError(f"{self.world.source}: no marker {name!r} (known: {known})")


def _marker(r: WorldReader, entry: Any, key: str) -> Marker:
    r.mapping(entry, key, _MARKER_KEYS)
    survivor = entry.get("survivor")
    if survivor is not None and not isinstance(survivor, bool):
        raise r.fail(f"{key}.survivor", f"expected true or false, got {survivor!r}")
    optional = {k: entry.get(k) for k in ("room", "colour")}
    for k, v in optional.items():
        if v is not None:
            r.text(v, f"{key}.{k}")
    return Marker(
        name=r.text(r.field(entry, key, "name"), f"{key}.name"),
        x=r.num_field(entry, key, "x"),
        y=r.num_field(entry, key, "y"),
        radius=r.num_field(entry, key, "radius", positive=True),
        survivor=survivor,
        **optional,
    )


def parse_course_world(doc: Any, source: str = "<memory>") -> CourseWorld:
    """Build the :class:`CourseWorld` of a parsed world document.

    Raises:
        WorldError: A key is missing, unknown or malformed, or a name repeats (file and key
            named).
    """
    world = parse_world(doc, source, sections=(MARKERS,))
    r = WorldReader(source)
    markers = tuple(_marker(r, e, f"{MARKERS}[{i}]") for i, e in enumerate(r.items(doc, MARKERS)))
    seen: set[str] = set()
    for marker in markers:
        if marker.name in seen:
            raise r.fail(marker.name, "duplicate marker name")
        seen.add(marker.name)
    return CourseWorld(world, markers)


def load_course_world(path: str | Path = COURSE_WORLD) -> CourseWorld:
    """Load a world file in the course's format (default: the course world).

    Raises:
        WorldError: The file cannot be read, is not YAML, or is malformed.
    """
    return parse_course_world(read_world_file(path), str(path))


def main(argv: Sequence[str] | None = None) -> int:
    """Rasterise the course world into the simulator's default map (``maps/``)."""
    from sar_framework.sim.map_writer import write_map
    from sar_framework.sim.occupancy import DEFAULT_MAP_PREFIX, rasterize

    args = list(sys.argv[1:] if argv is None else argv)
    path = Path(args[0]) if args else COURSE_WORLD
    try:
        course = load_course_world(path)
    except WorldError as exc:
        sys.stderr.write(f"error: {exc}\n")
        return 1
    grid = rasterize(course.world)
    pgm, yaml_file = write_map(grid, DEFAULT_MAP_PREFIX)
    sys.stdout.write(f"wrote {pgm} and {yaml_file} ({grid.width}x{grid.height} cells)\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
