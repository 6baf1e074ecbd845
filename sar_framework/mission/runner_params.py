"""The tree runner's parameters (``sar_mission_runner``): its own, once (an app's are the app's).

No ROS here: :data:`RUNNER_PARAMETERS` is read by the runner
(:mod:`sar_framework.runner.settings`), by ``sar-tree run``'s
checks of the parameter file and of ``--runner-param``, and by the documentation
(docs/reference/parameters.md, checked by a test).
"""

from __future__ import annotations

from sar_framework.engine.param import Param
from sar_framework.mission.completion import COMPLETION_MODES, DEFAULT_COMPLETION
from sar_framework.mission.params_check import USE_SIM_TIME

DEFAULT_TREE = "trees/search_and_rescue.yaml"
"""The tree file when none is named (the checkout's copy when the working folder has none)."""


def pose_params(prefix: str, what: str, default: object) -> tuple[Param, ...]:
    """``PREFIX.x``, ``PREFIX.y`` and ``PREFIX.yaw``: a pose in the map frame, as parameters."""
    return (Param(f"{prefix}.x", float, default, f"{what}: x (map frame)", unit="m"),
            Param(f"{prefix}.y", float, default, f"{what}: y (map frame)", unit="m"),
            Param(f"{prefix}.yaw", float, default, f"{what}: heading", unit="rad"))


TICK_RATE_HZ = Param("tick_rate_hz", float, 2.0, "tree ticks per second (ROS time)",
                     exclusive_minimum=0.0, unit="Hz")

RUNNER_PARAMETERS: tuple[Param, ...] = (
    TICK_RATE_HZ,
    Param("completion", str, DEFAULT_COMPLETION, "how the mission ends: end, once, rest, "
          "forever, or auto (the tree file's completion key, else end)",
          enum=COMPLETION_MODES),
    Param("tree", str, DEFAULT_TREE, "the tree file"),
    Param("plugin_path", str | list[str], "", "extra plugin files, directories or modules "
          "(a list, or one string separated by the OS path separator)"),
    Param("set", str | list[str], "", "initial values of entries the tree declares, "
          "NAME=VALUE each (a list, or one string split as a shell splits words; "
          "sar-tree run --set, the launch argument set:=)"),
    Param("exit_on_completion", bool, False,
          "end the runner once the mission is complete: exit 0 on SUCCESS, 1 on FAILURE"),
    Param("print_tree", bool, False, "log the tree whenever a status changes"),
    Param("watch_tree", bool, False, "reload the tree between ticks when its file or an "
          "include changes (sar-tree run --reload; the ~/reload service always can)"),
    Param("status_file", str, "", "JSON status file, kept current ('' = none)"),
    Param("seed_amcl", bool, True, "seed AMCL with initial_pose and wait for Nav2 before "
          "ticking"),
    Param("nav2_timeout_wall_s", float, 90.0, "bound of the Nav2 start-up (wall clock: it "
          "holds when no /clock comes)", exclusive_minimum=0.0, unit="s"),
    Param("setup_timeout_wall_s", float, 60.0, "bound of the tree's setup() (wall clock: it "
          "holds when a setup() blocks)", exclusive_minimum=0.0, unit="s"),
    Param("sim_timeout_s", float, 0.0, "stop the tree and exit 4 once it has ticked this "
          "long on its ROS clock (/clock time with use_sim_time; 0 = no bound; "
          "sar-tree run --sim-timeout)", minimum=0.0, unit="s"),
    *pose_params("initial_pose", "AMCL seed (spawn pose)", 0.0),
    USE_SIM_TIME,
)
"""The runner's own parameters (an app's are its own: :attr:`~sar_framework.app.App.parameters`)."""
