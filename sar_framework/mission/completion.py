"""How a mission ends: the runner's ``completion`` parameter (plain Python, no ROS).

| mode | the mission is complete... |
| --- | --- |
| ``end`` | (the default) when the tree reaches its declared end: the root FAILS, or the root |
|         | SUCCEEDS through the ``one_shot`` on its final path as that one_shot latches (a |
|         | tree with no ``one_shot`` on its final path: the root's first SUCCESS) |
| ``once`` | the first tick the root returns SUCCESS or FAILURE |
| ``rest`` | when the tree is at rest: the root keeps one terminal status over two ticks |
|          | and nothing changes (kept for trees that idle at their end; it is a guess) |
| ``forever`` | never: the tree is ticked until Ctrl-C (the course's node) |
| ``auto`` | the runner's default: the tree file's top-level ``completion`` key, else ``end`` |

With ``end``, ``once`` and ``rest`` the tree is never ticked again once the mission is
complete, so a finished mission cannot start over. "The final path" follows the last child
of every composite and the child of every decorator from the root. The reference tree's
root is a reactive selector whose last child is the ``one_shot`` around ``NavigateToBase``:
its root succeeds after *every* visit (the patrol's branch), and the mission ends only when
the one_shot has latched. A memory sequence [time budget around a repeat, then a one_shot
home] ends when the one_shot home latches; it is never ticked again after that, so the
robot is not sent off on a second patrol. ``end`` never needs another tick (with its side
effects) to find out whether the mission is over.

Declare it in the tree file (``completion: once``); the runner's parameter (mission
parameter file ``completion: once`` or ``--runner-param completion:=once``) overrides it.
``sar-tree validate`` prints what applies.
"""

from __future__ import annotations

from typing import Any

from sar_framework.engine.nodes.node_kinds import TREE_COMPLETIONS

COMPLETION_MODES = ("auto", *TREE_COMPLETIONS)
"""Every value of the ``completion`` parameter."""
DEFAULT_COMPLETION = "auto"
#: What ``auto`` becomes when the tree file does not declare its completion.
TREE_DEFAULT_COMPLETION = "end"
COMPLETION_HELP = (
    "completion (mission parameter `completion`, --runner-param completion:=MODE, or the tree "
    "file's top-level `completion:`): end (default) = the mission ends when the tree reaches "
    "its declared end (the root fails, or succeeds through the one_shot on its final path as "
    "it latches; without such a one_shot, the root's first SUCCESS); once = the root's first "
    "SUCCESS or FAILURE; rest = when the tree is at rest (root status unchanged over two "
    "ticks); forever = tick until Ctrl-C; auto = the tree file's key, else end."
)

_MEANING = {
    "end": "the mission ends when the tree reaches its declared end",
    "once": "the first SUCCESS or FAILURE of the root ends the mission",
    "rest": "the mission ends when the tree is at rest",
    "forever": "ticked until Ctrl-C",
}


def ending_one_shot(spec: Any) -> Any | None:
    """The ``one_shot`` on the tree's final path, or None.

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
        mode: One of :data:`COMPLETION_MODES` (the runner's parameter).
        spec: The tree's ``TreeSpec``.

    Returns:
        ``(mode, why)`` where ``mode`` is ``end``, ``once``, ``rest`` or ``forever``.

    Raises:
        ValueError: An unknown mode.
    """
    if mode not in COMPLETION_MODES:
        raise ValueError(f"completion must be one of {', '.join(COMPLETION_MODES)}, "
                         f"got {mode!r}")
    declared = getattr(spec, "completion", "") or ""
    if mode != "auto":
        source = "set in the parameters"
    elif declared:
        mode, source = declared, "declared in the tree file"
    else:
        mode, source = TREE_DEFAULT_COMPLETION, "default"
    why = f"{source}; {_MEANING[mode]}"
    if mode == "end":
        end = ending_one_shot(spec)
        why += (f": when one_shot {end.name} [{end.uid}] latches, or the root fails" if end
                else ": the root's first SUCCESS or FAILURE (no one_shot on its final path)")
    return mode, why


def describe_completion(mode: str, spec: Any) -> str:
    """One line for the console: ``completion: end (default; ...)``."""
    effective, why = resolve_completion(mode, spec)
    return f"completion: {effective} ({why})"
