"""config/nav2_params.yaml against upstream Jazzy ``nav2_bringup/params/nav2_params.yaml``.

Nav2's C++ servers cannot run here, so this is the check that our file still speaks
Jazzy: every node section we configure is one upstream's bringup configures or starts,
every ``plugin:`` we load is named as upstream names it, and every key we set is one
upstream's file sets for that node (for a plugin: for a plugin of the same type), or one
in :data:`KNOWN_ELSEWHERE`, each with the reason upstream's example file leaves it out.

Needs only upstream's nav2_bringup files: from ``$SAR_ROS_OVERLAY_SRC``,
``../shared/ros-overlay/src`` next to the repository, or the venv's ``share/`` (where set-up
installs nav2_bringup's launch and params).
"""

from __future__ import annotations

import os
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import yaml

REPO = Path(__file__).resolve().parents[2]
OURS = REPO / "config" / "nav2_params.yaml"
UPSTREAM_PARAMS = Path("nav2_bringup") / "params" / "nav2_params.yaml"
UPSTREAM_LAUNCH = Path("nav2_bringup") / "launch"

#: Keys that Nav2 Jazzy's servers declare but upstream's example leaves at their default.
#: (node section, key): why we set it.
KNOWN_ELSEWHERE: dict[tuple[str, str], str] = {
    ("amcl", "set_initial_pose"): "the runner seeds AMCL on /initialpose; default is false",
    ("amcl", "always_reset_initial_pose"): "pinned off so a map reload keeps the pose",
    ("amcl", "first_map_only"): "pinned off: AMCL follows map updates",
    ("controller_server", "odom_topic"): "ROSbot's fused odometry is /odometry/filtered",
    ("controller_server", "enable_stamped_cmd_vel"): "ROSbot takes TwistStamped (Jazzy: "
                                                     "default false)",
    ("behavior_server", "enable_stamped_cmd_vel"): "as controller_server",
    ("velocity_smoother", "enable_stamped_cmd_vel"): "as controller_server",
    ("collision_monitor", "enable_stamped_cmd_vel"): "as controller_server",
    ("docking_server", "enable_stamped_cmd_vel"): "as controller_server",
    ("local_costmap", "transform_tolerance"): "Costmap2DROS parameter; ROSbot TF latency",
    ("global_costmap", "transform_tolerance"): "Costmap2DROS parameter; ROSbot TF latency",
    ("FollowPath", "enforce_path_inversion"): "MPPI parameter, pinned off (no cusps with "
                                              "NavFn)",
}


def upstream_root() -> Path | None:
    """The upstream source tree holding nav2_bringup, or None."""
    candidates = [os.environ.get("SAR_ROS_OVERLAY_SRC", ""),
                  str(REPO.parent / "shared" / "ros-overlay" / "src"),
                  str(Path(sys.prefix) / "share")]
    for candidate in filter(None, candidates):
        if (Path(candidate) / UPSTREAM_PARAMS).is_file():
            return Path(candidate)
    return None


ROOT = upstream_root()
pytestmark = pytest.mark.skipif(
    ROOT is None, reason="no upstream nav2_bringup params (../shared/ros-overlay/src, "
                         "$SAR_ROS_OVERLAY_SRC or the venv's share/): nothing to compare with")


@pytest.fixture(scope="module")
def ours() -> dict[str, Any]:
    return yaml.safe_load(OURS.read_text(encoding="utf-8"))


@pytest.fixture(scope="module")
def upstream() -> dict[str, Any]:
    assert ROOT is not None
    return yaml.safe_load((ROOT / UPSTREAM_PARAMS).read_text(encoding="utf-8"))


@pytest.fixture(scope="module")
def upstream_launch_text() -> str:
    assert ROOT is not None
    return "\n".join(p.read_text(encoding="utf-8")
                     for p in sorted((ROOT / UPSTREAM_LAUNCH).glob("*.py")))


def node_sections(params: dict[str, Any]) -> Iterator[tuple[str, dict[str, Any]]]:
    """(node name, its ros__parameters) for every node, costmaps' nested form included."""
    for name, section in params.items():
        if not isinstance(section, dict):
            continue
        if "ros__parameters" in section:
            yield name, section["ros__parameters"]
        for inner, nested in section.items():
            if isinstance(nested, dict) and "ros__parameters" in nested:
                yield inner, nested["ros__parameters"]


def plugin_sections(section: dict[str, Any]) -> Iterator[dict[str, Any]]:
    """Every sub-section (at any depth) that names a ``plugin:``."""
    for value in section.values():
        if isinstance(value, dict):
            if "plugin" in value:
                yield value
            yield from plugin_sections(value)


def unknown_keys(ours: dict[str, Any], theirs: list[dict[str, Any]], node: str, where: str,
                 pool: list[dict[str, Any]]) -> list[str]:
    """Keys of ``ours`` that none of ``theirs`` (upstream's matching sections) sets.

    A plugin's section is compared with upstream's sections for the same plugin type,
    taken from ``pool`` (every plugin section of upstream's file: a costmap layer is the
    same class in the local and the global costmap).
    """
    known = {key for section in theirs for key in section}
    owner = where.rsplit(".", 1)[-1]
    problems = []
    for key, value in ours.items():
        path = f"{where}.{key}"
        if isinstance(value, dict) and "plugin" in value:
            same = [p for p in pool if p["plugin"] == value["plugin"]]
            if not same:
                problems.append(f"{path}: upstream never loads plugin {value['plugin']!r}")
                continue
            problems += unknown_keys(value, same, node, path, pool)
        elif isinstance(value, dict):
            inner = [s[key] for s in theirs if isinstance(s.get(key), dict)]
            if not inner:
                problems.append(f"{path}: no such section upstream")
                continue
            problems += unknown_keys(value, inner, node, path, pool)
        elif key not in known and (node, key) not in KNOWN_ELSEWHERE \
                and (owner, key) not in KNOWN_ELSEWHERE:
            problems.append(f"{path}: upstream's {node} section does not set it")
    return problems


def test_every_node_we_configure_is_one_upstream_configures_or_starts(
        ours: dict[str, Any], upstream: dict[str, Any], upstream_launch_text: str) -> None:
    theirs = dict(node_sections(upstream))
    missing = [name for name, _ in node_sections(ours)
               if name not in theirs and f"'{name}'" not in upstream_launch_text]
    assert not missing, f"node sections upstream neither configures nor starts: {missing}"


def test_every_plugin_we_load_is_named_as_upstream_names_it(
        ours: dict[str, Any], upstream: dict[str, Any]) -> None:
    theirs = {p["plugin"] for _, section in node_sections(upstream)
              for p in plugin_sections(section)}
    ours_by_node = {name: {p["plugin"] for p in plugin_sections(section)}
                    for name, section in node_sections(ours)}
    assert ours_by_node["controller_server"] >= {"nav2_mppi_controller::MPPIController"}
    wrong = {name: sorted(plugins - theirs) for name, plugins in ours_by_node.items()
             if plugins - theirs}
    assert not wrong, f"plugins upstream Jazzy does not name this way: {wrong}"


def test_behaviour_ids_and_critics_match_upstream(ours: dict[str, Any],
                                                   upstream: dict[str, Any]) -> None:
    mine, theirs = dict(node_sections(ours)), dict(node_sections(upstream))
    for node, key in (("behavior_server", "behavior_plugins"), ("bt_navigator", "navigators"),
                      ("planner_server", "planner_plugins"),
                      ("smoother_server", "smoother_plugins")):
        assert set(mine[node][key]) <= set(theirs[node][key]), (node, key)
        for plugin_id in mine[node][key]:
            assert mine[node][plugin_id]["plugin"] == theirs[node][plugin_id]["plugin"], plugin_id
    follow, upstream_follow = (s["controller_server"]["FollowPath"] for s in (mine, theirs))
    assert set(follow["critics"]) <= set(upstream_follow["critics"])


def test_no_key_we_set_is_unknown_upstream(ours: dict[str, Any], upstream: dict[str, Any],
                                           upstream_launch_text: str) -> None:
    theirs = dict(node_sections(upstream))
    # Upstream's launch files set these for the nodes (SetParameter / parameters=[...]).
    launch_set = {key for key in ("use_sim_time", "yaml_filename")
                  if f"'{key}'" in upstream_launch_text}
    pool = [p for section in theirs.values() for p in plugin_sections(section)]
    problems = []
    for name, section in node_sections(ours):
        trimmed = {k: v for k, v in section.items() if k not in launch_set}
        problems += unknown_keys(trimmed, [theirs.get(name, {})], name, name, pool)
    assert not problems, "keys upstream Jazzy does not know:\n" + "\n".join(problems)


def test_the_allowlist_holds_only_keys_we_still_set(ours: dict[str, Any]) -> None:
    """A stale allowlist entry would hide a future difference."""
    flat: set[tuple[str, str]] = set()

    def walk(section: dict[str, Any], owner: str) -> None:
        for key, value in section.items():
            if isinstance(value, dict):
                walk(value, key)
            else:
                flat.add((owner, key))

    for name, section in node_sections(ours):
        walk(section, name)
    assert set(KNOWN_ELSEWHERE) <= flat, set(KNOWN_ELSEWHERE) - flat
