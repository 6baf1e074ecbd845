"""The fleet file: which robots the simulator serves, each under its namespace (plain Python).

A small YAML file, nav2_bringup's ``robots:=`` argument written as a file::

    robots:
      - name: robot1
        pose: {x: -1.0, y: 0.5, yaw: 0.0}
      - name: robot2
        pose: {x: 0.0, y: 0.5}

Each name becomes a ROS namespace (``/robot1/navigate_to_pose``...), so it must be a
valid namespace token (a letter, then letters, digits or underscores) and unique. ``yaw``
defaults to 0. :func:`load_fleet` reports every problem at once, each as
``file:line:col: problem`` (:class:`FleetFileError`).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

from yaml.nodes import MappingNode, Node, ScalarNode, SequenceNode

from sar_framework.engine.diagnostics import Diagnostic, SourceLocation
from sar_framework.engine.reading.yaml_source import Reader, location, read
from sar_framework.sim.world import Pose2D

__all__ = ["FleetFileError", "FleetRobot", "crowded_spawns", "load_fleet"]

_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")
_ROBOT_KEYS = ("name", "pose")
_POSE_KEYS = ("x", "y", "yaw")


class FleetFileError(ValueError):
    """A fleet file that cannot be used; the message has one ``file:line:col: ...`` per line.

    Attributes:
        diagnostics: Every problem found.
    """

    def __init__(self, diagnostics: list[Diagnostic]) -> None:
        self.diagnostics = diagnostics
        super().__init__("\n".join(f"{d.location}: {d.message}" for d in diagnostics))


@dataclass(frozen=True)
class FleetRobot:
    """One robot of the fleet.

    Attributes:
        name: Its namespace, without slashes (``robot1``).
        spawn: Where it starts, in the map frame.
        where: Where it is named in the fleet file (for later messages).
    """

    name: str
    spawn: Pose2D
    where: SourceLocation


def _number(r: Reader, node: Node, key: str) -> float | None:
    ok, value = r.scalar(node) if type(node) is ScalarNode else (False, None)
    if ok and not isinstance(value, bool) and isinstance(value, (int, float)) \
            and math.isfinite(value):
        return float(value)
    if type(node) is not ScalarNode or ok:
        r.error(node, f"{key}: expected a finite number, got {getattr(node, 'value', node)!r}")
    return None


def _mapping(r: Reader, node: Node, key: str, allowed: tuple[str, ...]
             ) -> dict[str, Node] | None:
    if type(node) is not MappingNode:
        r.error(node, f"{key}: expected a mapping with {', '.join(allowed)}")
        return None
    entries = r.items(node)
    if entries is None:
        return None
    out: dict[str, Node] = {}
    for name, key_node, value in entries:
        if name in allowed:
            out[name] = value
        else:
            r.error(key_node, f"{key}.{name}: unknown key (allowed: {', '.join(allowed)})")
    return out


def _robot(r: Reader, node: Node, index: int, seen: dict[str, int]) -> FleetRobot | None:
    key = f"robots[{index}]"
    fields = _mapping(r, node, key, _ROBOT_KEYS)
    if fields is None:
        return None
    for missing in (k for k in _ROBOT_KEYS if k not in fields):
        r.error(node, f"{key}: missing key '{missing}'")
    name_node, pose_node = fields.get("name"), fields.get("pose")
    name = None
    if name_node is not None:
        ok, value = r.scalar(name_node) if type(name_node) is ScalarNode else (False, None)
        if not (ok and isinstance(value, str) and _NAME.match(value)):
            r.error(name_node, f"{key}.name: expected a namespace name (a letter, then "
                    f"letters, digits or '_'), got {getattr(name_node, 'value', '...')!r}")
        elif value in seen:
            r.error(name_node, f"{key}.name: robot '{value}' already named on line "
                    f"{seen[value]}")
        else:
            name = value
            seen[value] = name_node.start_mark.line + 1
    pose = _mapping(r, pose_node, f"{key}.pose", _POSE_KEYS) if pose_node is not None else None
    if pose is None:
        return None
    for missing in (k for k in ("x", "y") if k not in pose):
        r.error(pose_node, f"{key}.pose: missing key '{missing}'")
    values = {k: _number(r, v, f"{key}.pose.{k}") for k, v in pose.items()}
    if name is None or values.get("x") is None or values.get("y") is None \
            or ("yaw" in pose and values["yaw"] is None):
        return None
    spawn = Pose2D(values["x"], values["y"], values.get("yaw") or 0.0)  # type: ignore[arg-type]
    return FleetRobot(name, spawn, location(node, r.file))


def parse_fleet(root: Node | None, file: str, diagnostics: list[Diagnostic]
                ) -> tuple[FleetRobot, ...]:
    """Read the robots of a composed fleet file, appending problems to ``diagnostics``.

    Args:
        root: The composed document (None: empty file).
        file: The file name to print.
        diagnostics: Where problems are appended.

    Returns:
        The robots that were read without problems.
    """
    r = Reader(file, diagnostics)
    top = SourceLocation(file, 1, 1)
    if root is None:
        diagnostics.append(Diagnostic(top, "empty fleet file: expected 'robots:' with a list"))
        return ()
    fields = _mapping(r, root, "<top level>", ("robots",))
    if fields is None:
        return ()
    robots_node = fields.get("robots")
    if robots_node is None:
        r.error(root, "missing key 'robots'")
        return ()
    if type(robots_node) is not SequenceNode or not robots_node.value:
        r.error(robots_node, "robots: expected a non-empty list of {name, pose}")
        return ()
    items = r.sequence(robots_node) or []
    seen: dict[str, int] = {}
    robots = [_robot(r, item, i, seen) for i, item in enumerate(items)]
    return tuple(robot for robot in robots if robot is not None)


def load_fleet(path: str | Path) -> tuple[FleetRobot, ...]:
    """Load and check a fleet file.

    Args:
        path: The file.

    Returns:
        The robots, in file order.

    Raises:
        FleetFileError: Every problem, each with file, line and column.
    """
    file = str(path)
    root, diagnostics = read(Path(path), file)
    robots = parse_fleet(root, file, diagnostics) if not diagnostics else ()
    if diagnostics:
        raise FleetFileError(diagnostics)
    return robots


def crowded_spawns(robots: tuple[FleetRobot, ...], gap: float) -> list[str]:
    """One ``file:line:col: ...`` problem per robot spawned within ``gap`` of an earlier one.

    Args:
        robots: The fleet, in file order.
        gap: The least distance between two spawns (the simulator's two footprints).
    """
    return [f"{a.where}: robot '{a.name}' spawns within {gap:g} m (two footprints) of "
            f"robot '{b.name}' ({b.where})"
            for i, a in enumerate(robots) for b in robots[:i]
            if math.dist((a.spawn.x, a.spawn.y), (b.spawn.x, b.spawn.y)) <= gap]
