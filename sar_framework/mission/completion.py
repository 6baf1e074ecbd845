"""How a mission ends: the runner's ``completion`` parameter (plain Python, no ROS).

| mode | the mission is complete... |
| --- | --- |
| ``once`` | the first tick the root returns SUCCESS or FAILURE; the tree is not ticked again |
| ``rest`` | when the tree is at rest: the root keeps one terminal status over two ticks |
|          | and nothing changes (a reactive tree idling at a ``one_shot`` at its end) |
| ``forever`` | never: the tree is ticked until Ctrl-C (the course's node) |
| ``auto`` | (the default) ``rest`` when the tree ends with a ``one_shot``, else ``once`` |

"Ends with" follows the last child of every composite and the child of every decorator
from the root. The reference tree's root is a reactive selector whose last child is the
``one_shot`` around ``NavigateToBase``: its root succeeds after *every* zone and the
mission is over only when it rests at that one_shot. A tree without a one_shot at its end
(a time budget around a repeat, then "go home") runs once: ticking it again would send
the robot off again.

Set it in the mission parameter file (``completion: once``) or with
``--runner-param completion:=once``.
"""

from __future__ import annotations

from typing import Any

COMPLETION_MODES = ("auto", "once", "rest", "forever")
"""Every value of the ``completion`` parameter."""
DEFAULT_COMPLETION = "auto"
COMPLETION_HELP = (
    "completion (mission parameter `completion`, or --runner-param completion:=MODE): "
    "once = the mission ends the first time the root returns SUCCESS or FAILURE (the tree "
    "is not ticked again); rest = it ends when the tree is at rest (root status unchanged "
    "over two ticks, nothing else changed); forever = tick until Ctrl-C; auto (default) = "
    "rest when the tree ends with a one_shot, else once."
)


def ending_one_shot(spec: Any) -> Any | None:
    """The ``one_shot`` the tree ends with, or None.

    Args:
        spec: A :class:`~sar_framework.engine.spec.TreeSpec`.

    Returns:
        The ``NodeSpec`` reached from the root by taking the last child of each node
        until a ``one_shot`` or a leaf; None when that is not a ``one_shot``.
    """
    node = spec.root
    while node.kind != "one_shot" and node.children:
        node = node.children[-1]
    return node if node.kind == "one_shot" else None


def resolve_completion(mode: str, spec: Any) -> tuple[str, str]:
    """The effective mode for a tree, and why, in words.

    Args:
        mode: One of :data:`COMPLETION_MODES`.
        spec: The tree's ``TreeSpec``.

    Returns:
        ``(mode, why)`` where ``mode`` is ``once``, ``rest`` or ``forever``.

    Raises:
        ValueError: An unknown mode.
    """
    if mode not in COMPLETION_MODES:
        raise ValueError(f"completion must be one of {', '.join(COMPLETION_MODES)}, "
                         f"got {mode!r}")
    end = ending_one_shot(spec)
    ends = f"the tree ends with one_shot {end.name} [{end.uid}]" if end else \
        "the tree does not end with a one_shot"
    if mode == "auto":
        mode = "rest" if end else "once"
        source = f"auto: {ends}"
    else:
        source = "set in the parameters"
    meaning = {
        "once": "the first SUCCESS or FAILURE of the root ends the mission",
        "rest": "the mission ends when the tree is at rest",
        "forever": "ticked until Ctrl-C",
    }[mode]
    return mode, f"{source}; {meaning}"


def describe_completion(mode: str, spec: Any) -> str:
    """One line for the console: ``completion: rest (auto: ...; ...)``."""
    effective, why = resolve_completion(mode, spec)
    return f"completion: {effective} ({why})"
