"""The studio's hot reload: the edited tree saved to the mission's file and swapped in.

``POST /api/reload`` (:mod:`.server`) calls :func:`apply_to_mission`: the editor's text is
written to the tree file the running mission's runner ticks (the live studio's ``--tree`` or
``--run`` file, :class:`~sar_framework.studio.editor.TreeEditor`), then the runner is asked
to read it again through its ``~/reload`` service (docs/hot-reload.md). Its answer goes back
to the page as it is: the swap's summary, or the diagnostics of a refused tree (the running
tree then goes on unchanged). Asking is a callable given by the live studio
(:meth:`sar_framework.studio.ros_feed.LiveFeed.reload`), so this module has no ROS.

A studio that does not know the mission's tree file (``live`` without ``--tree``/``--run``,
or ``edit``) refuses with what to do instead, and writes nothing.

No ROS here.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from sar_framework.studio.safety import RefusedError

if TYPE_CHECKING:
    from sar_framework.studio.editor import TreeEditor

#: Asks the runner to reload its tree file: whether it swapped it, and its message.
AskReload = Callable[[], tuple[bool, str]]

NO_MISSION = ("no running mission to apply it to: `sar-tree studio edit` only edits the file; "
              "start `sar-tree studio live --run TREE`, or `live --tree FILE` with the file "
              "the mission's runner ticks")
NO_TREE_FILE = ("the studio does not know the running mission's tree file: start it with "
                "`sar-tree studio live --tree FILE` (the file the runner ticks) or `--run TREE`")


class ReloadUnavailableError(RuntimeError):
    """The runner's reload service cannot be reached (no mission, or it did not answer)."""


def apply_to_mission(text: str, editor: TreeEditor | None, ask: AskReload | None,
                     live: bool) -> tuple[int, dict[str, Any]]:
    """Save ``text`` as the mission's tree file and ask the runner to swap it in.

    Args:
        text: The tree the page holds.
        editor: The editor of the mission's tree file (None when the studio does not know it).
        ask: Asks the runner's reload service (None without a ROS feed).
        live: Whether the studio shows a running mission.

    Returns:
        The HTTP status and the page's document: ``{"swapped", "message", "saved", "ok",
        "diagnostics"}`` when the runner answered (200, swapped or refused), else
        ``{"error", ...}``.
    """
    if not live or ask is None:
        return 409, {"error": NO_MISSION}
    if editor is None:
        return 409, {"error": NO_TREE_FILE}
    try:
        checked = editor.save(text)
    except RefusedError as err:
        return 403, {"error": str(err)}
    saved = {"saved": checked["saved"], "ok": checked["ok"],
             "diagnostics": checked["diagnostics"]}
    try:
        swapped, message = ask()
    except ReloadUnavailableError as err:
        return 503, {"error": f"saved to {checked['saved']} but not applied: {err}", **saved}
    return 200, {"swapped": swapped, "message": message, **saved}
