"""The plugin ids the simulated Nav2 servers know: ``config/nav2_params.yaml``'s plugin names.

Plain Python. A goal names its plugin by id (``planner_id``, ``controller_id``,
``goal_checker_id``, ``progress_checker_id``, ``smoother_id``); an empty id means the server's
only plugin, as in Nav2 when exactly one is loaded. An unknown id fails the goal with the
action's code (INVALID_PLANNER, INVALID_CONTROLLER, INVALID_SMOOTHER; an unknown checker
is a ControllerException, FollowPath's UNKNOWN). tests/sim checks these names against the
params file.
"""

from __future__ import annotations

PLANNERS = ("GridBased",)
"""``planner_server.planner_plugins``."""
CONTROLLERS = ("FollowPath",)
"""``controller_server.controller_plugins``."""
GOAL_CHECKERS = ("goal_checker",)
"""``controller_server.goal_checker_plugins``."""
PROGRESS_CHECKERS = ("progress_checker",)
"""``controller_server.progress_checker_plugins``."""
SMOOTHERS = ("simple_smoother",)
"""``smoother_server.smoother_plugins``."""


def unknown_id(given: str, known: tuple[str, ...], what: str) -> str | None:
    """The error message for a plugin id the server does not have, or None if it is known.

    Args:
        given: The goal's id ("" = the only plugin).
        known: The server's plugin names.
        what: ``planner``, ``controller``... for the message.
    """
    if given == "" or given in known:
        return None
    return (f"{what} id {given!r} is not loaded; available: {', '.join(known)} "
            "(config/nav2_params.yaml)")
