"""The runner's own parameters (besides the mission's), read with guarded declarations.

| parameter | type | default | meaning |
| --- | --- | --- | --- |
| ``tree`` | str | ``trees/search_and_rescue.yaml`` | the tree file |
| ``plugin_path`` | str | ``""`` | extra plugin files/dirs/modules, ``os.pathsep``-separated |
| ``exit_on_completion`` | bool | false | end once the mission is complete: 0 SUCCESS, 1 FAILURE |
| ``completion`` | str | ``auto`` | ``auto``, ``once``, ``rest`` or ``forever`` (below) |
| ``print_tree`` | bool | false | log the unicode tree whenever a status changes |
| ``status_file`` | str | ``""`` | JSON status file (off when empty) |
| ``seed_amcl`` | bool | true | seed AMCL and wait for Nav2 before ticking |
| ``nav2_timeout_s`` | float | 30.0 | bound of the Nav2 start-up |
| ``setup_timeout_s`` | float | 15.0 | bound of the tree's ``setup()`` |
| ``initial_pose.{x,y,yaw}`` | float | 0.0 | the AMCL seed (spawn pose), frame ``map`` |

``completion`` (:mod:`sar_framework.mission.completion`): ``once`` ends the mission the
first tick the root is SUCCESS or FAILURE; ``rest`` when the tree is at rest (the root keeps
one terminal status over two ticks and nothing changes); ``forever`` never; ``auto`` is
``rest`` for a tree that ends with a ``one_shot``, else ``once``.

``tick_rate_hz`` and the zones come from the mission parameters
(:mod:`sar_framework.mission.params`); ``use_sim_time`` is ROS's own.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from sar_framework.mission.completion import COMPLETION_MODES, DEFAULT_COMPLETION
from sar_framework.mission.params import ParamReader, declare_default
from sar_framework.mission.params_file import KeyLocation
from sar_framework.ros.nav2_startup import InitialPose

if TYPE_CHECKING:
    from rclpy.node import Node

DEFAULT_TREE = "trees/search_and_rescue.yaml"
_REPO_TREE = Path(__file__).resolve().parents[2] / DEFAULT_TREE


@dataclass(frozen=True)
class RunnerSettings:
    """What the runner was asked to do (see the module's table).

    Attributes:
        tree: The tree file, as given.
        plugin_paths: Extra plugin locations.
        exit_on_completion: End once the mission is complete.
        completion: ``auto``, ``once``, ``rest`` or ``forever``: how the mission ends.
        print_tree: Log the tree on every status change.
        status_file: The status file path, or "" for none.
        seed_amcl: Seed AMCL and wait for Nav2 first.
        nav2_timeout_s: Bound of the Nav2 start-up, seconds.
        setup_timeout_s: Bound of the tree's setup, seconds.
        initial_pose: The AMCL seed.
        use_sim_time: Whether the node follows ``/clock``.
    """

    tree: str
    plugin_paths: tuple[str, ...]
    exit_on_completion: bool
    completion: str
    print_tree: bool
    status_file: str
    seed_amcl: bool
    nav2_timeout_s: float
    setup_timeout_s: float
    initial_pose: InitialPose
    use_sim_time: bool


def default_tree() -> str:
    """Return ``trees/search_and_rescue.yaml`` (the checkout's copy when cwd has none)."""
    if not Path(DEFAULT_TREE).exists() and _REPO_TREE.exists():
        return str(_REPO_TREE)
    return DEFAULT_TREE


class _Typed(ParamReader):
    """Guarded declaration plus a type check that names the key in its error."""

    def flag(self, key: str, default: bool) -> bool:
        value = declare_default(self._node, key, default)
        if not isinstance(value, bool):
            raise self.error(key, f"must be true or false, got {value!r}")
        return value

    def text(self, key: str, default: str) -> str:
        value = declare_default(self._node, key, default)
        if not isinstance(value, str):
            raise self.error(key, f"must be a string, got {value!r}")
        return value

    def number(self, key: str, default: float, *, positive: bool = False) -> float:
        number = self.finite_number(key, declare_default(self._node, key, default))
        if positive and number <= 0:
            raise self.error(key, f"must be > 0, got {number:g}")
        return number

    def paths(self, key: str) -> tuple[str, ...]:
        value = declare_default(self._node, key, "")
        if isinstance(value, str):
            return tuple(p for p in value.split(os.pathsep) if p)
        if isinstance(value, (list, tuple)) and all(isinstance(v, str) for v in value):
            return tuple(v for v in value if v)
        raise self.error(key, f"must be a string ({os.pathsep}-separated) or a list of "
                               f"strings, got {value!r}")


def read_runner_settings(node: Node, *, source: str = "runner parameters",
                         locations: Mapping[str, KeyLocation] | None = None) -> RunnerSettings:
    """Declare (guarded) and read the runner's parameters.

    Args:
        node: The runner node (auto-declaring parameter overrides).
        source: Names where parameters came from when a key's file is unknown.
        locations: Where each key is set in the parameter files (adds line numbers).

    Returns:
        The settings.

    Raises:
        ParamsError: A parameter has the wrong type or an impossible value.
    """
    read = _Typed(node, source, locations or {})
    tree = read.text("tree", default_tree())
    if not tree:
        raise read.error("tree", "empty: name a tree file")
    completion = read.text("completion", DEFAULT_COMPLETION)
    if completion not in COMPLETION_MODES:
        raise read.error("completion", f"must be one of {', '.join(COMPLETION_MODES)}, "
                                       f"got {completion!r}")
    return RunnerSettings(
        tree=tree,
        plugin_paths=read.paths("plugin_path"),
        exit_on_completion=read.flag("exit_on_completion", False),
        completion=completion,
        print_tree=read.flag("print_tree", False),
        status_file=read.text("status_file", ""),
        seed_amcl=read.flag("seed_amcl", True),
        nav2_timeout_s=read.number("nav2_timeout_s", 30.0, positive=True),
        setup_timeout_s=read.number("setup_timeout_s", 15.0, positive=True),
        initial_pose=InitialPose(
            read.number("initial_pose.x", 0.0),
            read.number("initial_pose.y", 0.0),
            read.number("initial_pose.yaw", 0.0),
        ),
        use_sim_time=bool(node.get_parameter("use_sim_time").value),
    )
