"""The runner's own settings (besides the mission's), read from its parameter table.

Every parameter, its type, default, unit and range is declared once, in
:data:`sar_framework.mission.runner_params.RUNNER_PARAMETERS` (listed in
docs/reference/parameters.md);
:func:`read_runner_settings` declares the table on the node and turns it into
:class:`RunnerSettings`.

``completion`` (:mod:`sar_framework.mission.completion`): ``end`` ends the mission when the
tree reaches its declared end; ``once`` the first tick the root is SUCCESS or FAILURE;
``rest`` when the tree is at rest; ``forever`` never; ``auto`` is the tree file's
``completion`` key, else ``end``.
"""

from __future__ import annotations

import os
import shlex
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from sar_framework.engine.checking.initial_values import SetError, parse_settings
from sar_framework.mission.params_file import KeyLocation, ParamsError
from sar_framework.mission.runner_params import DEFAULT_TREE, RUNNER_PARAMETERS
from sar_framework.ros.parameters import declare_table
from sar_framework.runner.nav2_startup import InitialPose

if TYPE_CHECKING:
    from rclpy.node import Node

_REPO_TREE = Path(__file__).resolve().parents[2] / DEFAULT_TREE


@dataclass(frozen=True)
class RunnerSettings:
    """What the runner was asked to do (see :data:`RUNNER_PARAMETERS`).

    Attributes:
        tree: The tree file, as given.
        plugin_paths: Extra plugin locations.
        exit_on_completion: End once the mission is complete.
        completion: ``auto``, ``end``, ``once``, ``rest`` or ``forever``: how the mission
            ends.
        print_tree: Log the tree on every status change.
        watch_tree: Reload the tree when its file or an include changes.
        status_file: The status file path, or "" for none.
        seed_amcl: Seed AMCL and wait for Nav2 first.
        nav2_timeout_wall_s: Bound of the Nav2 start-up, seconds.
        setup_timeout_wall_s: Bound of the tree's setup, seconds.
        sim_timeout_s: Bound of the ticking on the node's ROS clock, seconds (0: none).
        initial_pose: The AMCL seed.
        use_sim_time: Whether the node follows ``/clock``.
        tick_rate_hz: How often the tree ticks (ROS time).
        initial_values: Entry name -> initial value given from outside the tree file
            (``set``), not yet checked against the tree.
    """

    tree: str
    plugin_paths: tuple[str, ...]
    exit_on_completion: bool
    completion: str
    print_tree: bool
    watch_tree: bool
    status_file: str
    seed_amcl: bool
    nav2_timeout_wall_s: float
    setup_timeout_wall_s: float
    sim_timeout_s: float
    initial_pose: InitialPose
    use_sim_time: bool
    tick_rate_hz: float
    initial_values: dict[str, Any] = field(default_factory=dict)


def default_tree() -> str:
    """Return ``trees/search_and_rescue.yaml`` (the checkout's copy when cwd has none)."""
    if not Path(DEFAULT_TREE).exists() and _REPO_TREE.exists():
        return str(_REPO_TREE)
    return DEFAULT_TREE


def read_runner_settings(node: Node, *, source: str = "runner parameters",
                         locations: Mapping[str, KeyLocation] | None = None) -> RunnerSettings:
    """Declare the runner's parameter table and read its settings.

    Args:
        node: The runner node (auto-declaring parameter overrides).
        source: Names where parameters came from when a key's file is unknown.
        locations: Where each key is set in the parameter files (adds line numbers).

    Returns:
        The settings.

    Raises:
        ParamsError: A parameter has the wrong type or an impossible value.
    """
    values = declare_table(node, RUNNER_PARAMETERS, source=source, locations=locations)
    tree = values["tree"]
    if tree == DEFAULT_TREE:
        tree = default_tree()
    if not tree:
        at = (locations or {}).get("tree")
        raise ParamsError(at.file if at else source, "tree", "empty: name a tree file",
                          at.line if at else None, at.col if at else None)
    paths = values["plugin_path"]
    if isinstance(paths, str):
        paths = paths.split(os.pathsep)
    sets = values["set"]
    try:
        initial = parse_settings(shlex.split(sets) if isinstance(sets, str) else sets)
    except (SetError, ValueError) as err:
        at = (locations or {}).get("set")
        raise ParamsError(at.file if at else source, "set", str(err),
                          at.line if at else None, at.col if at else None) from None
    return RunnerSettings(
        tree=tree,
        plugin_paths=tuple(p for p in paths if p),
        exit_on_completion=values["exit_on_completion"],
        completion=values["completion"],
        print_tree=values["print_tree"],
        watch_tree=values["watch_tree"],
        status_file=values["status_file"],
        seed_amcl=values["seed_amcl"],
        nav2_timeout_wall_s=float(values["nav2_timeout_wall_s"]),
        setup_timeout_wall_s=float(values["setup_timeout_wall_s"]),
        sim_timeout_s=float(values["sim_timeout_s"]),
        initial_pose=InitialPose(*(float(values[f"initial_pose.{k}"])
                                   for k in ("x", "y", "yaw"))),
        use_sim_time=bool(values["use_sim_time"]),
        tick_rate_hz=float(values["tick_rate_hz"]),
        initial_values=initial,
    )
