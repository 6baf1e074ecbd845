"""The studio's hot reload: the edited tree saved to the mission's file and swapped in.

``POST /api/reload`` (:mod:`.server`) calls :func:`apply_to_mission`: the editor's text is
written to the tree file the running mission's runner ticks (the live studio's ``--tree`` or
``--run`` file, :class:`~sar_framework.studio.editor.TreeEditor`), then the runner is asked
to read it again through its ``~/reload`` service (docs/how-to/hot-reload.md). Its answer goes back
to the page as it is: the swap's summary, or the diagnostics of a refused tree (the running
tree then goes on unchanged). Asking is a callable given by the live studio
(:meth:`sar_framework.studio.ros_feed.LiveFeed.reload`), so this module has no ROS.

A studio that does not know the mission's tree file (``live`` without ``--tree``/``--run``
whose runner has not named one found from here, or ``edit``) refuses with what to do
instead, and writes nothing; so does one whose file is not the one the runner says it ticks
(its parameter ``tree``, :func:`same_file`).

No ROS here.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

from sar_framework.studio.safety import RefusedError

if TYPE_CHECKING:
    from sar_framework.studio.editor import TreeEditor

#: Asks the runner to reload its tree file: whether it swapped it, and its message.
AskReload = Callable[[], tuple[bool, str]]
#: Asks the runner which tree file it ticks (None: it does not say).
AskTree = Callable[[], str | None]

NO_MISSION = ("no running mission to apply it to: `sar-tree studio edit` only edits the file; "
              "start `sar-tree studio live --run TREE`, or `live --tree FILE` with the file "
              "the mission's runner ticks")
NO_TREE_FILE = ("the studio does not know the running mission's tree file (its runner has "
                "not named one found from here): start it with `sar-tree studio live --tree "
                "FILE` (the file the runner ticks) or `--run TREE`")


class ReloadUnavailableError(RuntimeError):
    """The runner's reload service cannot be reached (no mission, or it did not answer)."""


def same_file(ticked: str, edited: Path) -> bool:
    """Whether the runner's ``tree`` (as it was given to it) can be the file ``edited``.

    An absolute path must be the same file; a relative one is taken from the studio's
    directory, else (the runner started elsewhere) must be the end of ``edited``'s path.
    """
    path = Path(ticked)
    if path.is_absolute():
        return path.resolve() == edited
    if (Path.cwd() / path).resolve() == edited:
        return True
    parts = tuple(part for part in path.parts if part != ".")
    return bool(parts) and ".." not in parts and edited.parts[-len(parts):] == parts


def apply_to_mission(text: str, editor: TreeEditor | None, ask: AskReload | None,
                     live: bool, ask_tree: AskTree | None = None) -> tuple[int, dict[str, Any]]:
    """Save ``text`` as the mission's tree file and ask the runner to swap it in.

    Args:
        text: The tree the page holds.
        editor: The editor of the mission's tree file (None when the studio does not know it).
        ask: Asks the runner's reload service (None without a ROS feed).
        live: Whether the studio shows a running mission.
        ask_tree: Asks which file the runner ticks (not checked when None, or it says none).

    Returns:
        The HTTP status and the page's document: ``{"swapped", "message", "saved", "ok",
        "diagnostics"}`` when the runner answered (200, swapped or refused), else
        ``{"error", ...}``.
    """
    if not live or ask is None:
        return 409, {"error": NO_MISSION}
    if editor is None:
        return 409, {"error": NO_TREE_FILE}
    ticked = ask_tree() if ask_tree is not None else None
    if ticked is not None and not same_file(ticked, editor.path):
        return 409, {"error": f"the running mission ticks {ticked}, not {editor.shown}: "
                              "nothing saved (give the studio its file with --tree)"}
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
