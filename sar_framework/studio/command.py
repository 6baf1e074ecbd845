"""``sar-tree studio live|replay|edit``: start the studio and print its address.

``live`` attaches to the mission running on this ROS domain (``sar-tree run``, ``ros2
launch``), or starts one with ``--run TREE``; given the mission's tree file (``--tree`` or
``--run``), it also edits that file and applies it to the mission (hot reload,
:mod:`.reload`); ``replay FILE.mcap`` opens a recording of
``sar-tree run --record``; ``edit TREE`` edits a tree file (:mod:`.editor`), which must
lie in the project, the working directory or a ``--root`` directory.

The server binds ``127.0.0.1`` unless ``--host`` says otherwise, on ``--port`` (a free
one by default), and prints the page's address with the session's token, as Jupyter
does. It serves until Ctrl-C.
"""

from __future__ import annotations

import argparse
import atexit
import contextlib
import shutil
import socket
import sys
import tempfile
import webbrowser
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Any

from sar_framework.app.discovery import view_apps
from sar_framework.studio.safety import (
    DEFAULT_HOST,
    MESSAGE_MAX_BYTES,
    new_token,
)

if TYPE_CHECKING:
    from sar_framework.child_process import ChildProcess
    from sar_framework.studio.editor import TreeEditor
    from sar_framework.studio.ros_feed import LiveFeed
    from sar_framework.studio.session import Session

EXIT_OK = 0
EXIT_USAGE = 2
REPO = Path(__file__).resolve().parents[2]


def configure(parser: argparse.ArgumentParser) -> None:
    """Add ``sar-tree studio``'s modes and arguments to ``parser``."""
    modes = parser.add_subparsers(dest="mode", metavar="MODE")
    modes.required = True
    live = modes.add_parser("live", help="show the mission running on this ROS domain",
                            description="Attach to the mission running on this ROS domain.")
    live.add_argument("--tree", metavar="FILE",
                      help="the mission's tree file, for its params and ports and to edit it "
                           "and apply it to the mission (default: the diagram is drawn from "
                           "what the runner publishes)")
    live.add_argument("--plugin-path", action="append", default=[], metavar="DIR",
                      help="a folder of leaf plugins the tree uses (repeatable)")
    live.add_argument("--run", metavar="TREE",
                      help="start the mission too: `sar-tree run TREE` with --params, "
                           "--speed and --plugin-path (stopped with the studio)")
    live.add_argument("--speed", type=float, metavar="X",
                      help="with --run: the simulator's speed factor")
    live.add_argument("--params", metavar="FILE",
                      help="mission parameter file (default: the file of the app the tree "
                      "uses; none for a tree without an app)")
    replay = modes.add_parser("replay", help="scrub through a recording (.mcap)",
                              description="Open a recording of sar-tree run --record.")
    replay.add_argument("recording", metavar="FILE.mcap")
    edit = modes.add_parser("edit", help="edit a tree file with live checks and its diagram",
                            description="Edit a tree file in the browser: the diagnostics of "
                                        "sar-tree validate while typing, the diagram redrawn "
                                        "on each valid change, save with the session token.")
    edit.add_argument("tree", metavar="TREE", help="the tree file (created on save)")
    edit.add_argument("--plugin-path", action="append", default=[], metavar="DIR",
                      help="a folder of leaf plugins the tree uses (repeatable)")
    edit.add_argument("--root", action="append", default=[], metavar="DIR",
                      help="a directory the studio may write in, besides the project and "
                           "the working directory (repeatable)")
    for mode in (live, replay, edit):
        mode.add_argument("--host", default=DEFAULT_HOST,
                          help=f"address to listen on (default: {DEFAULT_HOST}, this machine "
                               "only)")
        mode.add_argument("--port", type=int, default=0, help="port (default: a free one)")
        mode.add_argument("--open", action="store_true", help="open the page in a browser")


def _fail(text: str) -> int:
    sys.stderr.write(f"sar-tree studio: error: {text}\n")
    return EXIT_USAGE


def studio_command(args: argparse.Namespace) -> int:
    """``sar-tree studio``: serve until interrupted; return the exit code."""
    from sar_framework.studio.session import LIVE

    listener = _listen(args)  # first: a port in use is said before anything starts
    if isinstance(listener, int):
        return listener
    with listener:
        editor = _editor(args) if args.mode == "edit" else None
        if isinstance(editor, int):
            return editor
        session = _session(args, editor)
        if isinstance(session, int):
            return session
        feed = mission = None
        if session.mode == LIVE:
            from sar_framework.studio.ros_feed import LiveFeed

            feed = LiveFeed(session).start()
            mission = _start_mission(args) if args.run else None
        try:
            return _serve(session, args, listener, editor, feed)
        finally:
            if mission is not None:
                mission.stop(timeout=10.0)  # SIGINT: the mission cancels its goal and ends
            if feed is not None:
                feed.stop()


def _start_mission(args: argparse.Namespace) -> ChildProcess:
    """``sar-tree run`` of ``--run``, its output on this terminal."""
    from sar_framework.child_process import ChildProcess

    argv = [sys.executable, "-m", "sar_framework", "run", args.run]
    if args.params:
        argv += ["--params", args.params]
    if args.speed is not None:
        argv += ["--speed", f"{args.speed:g}"]
    for folder in args.plugin_path:
        argv += ["--plugin-path", folder]
    return ChildProcess(argv, "mission", die_with_parent=True).start()


def _params_file(args: argparse.Namespace) -> str:
    """``--params``, else the default of the tree's apps, else "".

    Every installed app's default serves while the tree is not known yet.
    """
    from sar_framework.app import AppError, discover_apps, tree_apps

    if args.params:
        return args.params
    tree = args.tree or args.run
    try:
        apps = tree_apps(tree, args.plugin_path) if tree else discover_apps()
    except AppError:
        apps = []
    return next((f for f in (app.default_params_file() for app in apps) if f), "")


def _editor(args: argparse.Namespace) -> TreeEditor | int:
    """The editor of ``edit TREE``, or the exit code when the file may not be edited."""
    from sar_framework.studio.editor import TreeEditor
    from sar_framework.studio.safety import RefusedError

    roots = [Path.cwd(), REPO, *(Path(r) for r in args.root)]
    try:
        return TreeEditor(Path(args.tree), roots, args.plugin_path)
    except RefusedError as err:
        return _fail(f"{err}; add its directory with --root")


def _session(args: argparse.Namespace, editor: TreeEditor | None) -> Session | int:
    """The session ``args`` ask for, or the exit code of what is wrong with them."""
    from sar_framework.studio.session import EDIT, LIVE, Session, replay_session
    from sar_framework.studio.world_view import world_view

    if args.mode == "edit" and editor is not None:
        session = Session(EDIT, None, world_view(None), editor.shown)
        session.edit = _edit_state(editor)
        checked = editor.check(session.edit["text"]) if session.edit["text"] else None
        session.tree = checked["tree"] if checked else None
        return session
    if args.mode == "replay":
        from sar_framework.recording.readback import RecordingError

        path = Path(args.recording).resolve()  # named here: its directory is given
        if not path.is_file():
            return _fail(f"recording not found: '{args.recording}'")
        folder = Path(tempfile.mkdtemp(prefix="sar_studio_"))
        atexit.register(shutil.rmtree, folder, ignore_errors=True)  # the replay's files
        try:
            session = replay_session(path, folder)
        except RecordingError as err:
            return _fail(str(err))
    else:
        tree = _live_tree(args)
        if isinstance(tree, int):
            return tree
        params = _params_file(args)
        session = Session(LIVE, tree, world_view(params if Path(params).is_file() else None),
                          "live")
        if args.tree or args.run:
            session.timeline.apps = view_apps(args.tree or args.run, args.plugin_path)
            edit_live(session, args.tree or args.run, args.plugin_path)
        else:  # the file the runner says it ticks, once it runs
            session.learn_tree = partial(learn_tree_file, session, args.plugin_path)
    return session


def edit_live(session: Session, path: str, plugin_paths: list[str]) -> None:
    """Let a live session edit the mission's tree file ``path`` and draw it from the file."""
    from sar_framework.studio.editor import TreeEditor
    from sar_framework.studio.tree_view import file_tree_view

    # the file the mission ticks, named on the command line or by its runner: that file only
    editor = TreeEditor(Path(path), [Path.cwd(), REPO, Path(path).resolve()], plugin_paths)
    session.draw_file = partial(file_tree_view, str(editor.path), plugin_paths)
    session.editor = editor  # before the page can see it: its checks need the editor
    session.edit = _edit_state(editor)


def learn_tree_file(session: Session, plugin_paths: list[str], ticked: str) -> None:
    """Edit and draw the tree file the mission's runner ticks, when it is found from here."""
    if session.editor is None and Path(ticked).is_file():
        session.timeline.apps = view_apps(ticked, plugin_paths)  # its plugins: apps' words
        edit_live(session, ticked, plugin_paths)
        session.redraw_from_file()


def _edit_state(editor: TreeEditor) -> dict[str, Any]:
    """What the page's editor starts from: the file, its text and the completions."""
    return {"path": editor.shown, "text": editor.text(), "completions": editor.completions()}


def _live_tree(args: argparse.Namespace) -> dict[str, Any] | int | None:
    """The tree view of ``--tree`` (else ``--run``); None, or the exit code of a bad one."""
    path = args.tree or args.run
    if not path:
        return None
    from sar_framework.engine.api import validate
    from sar_framework.studio.tree_view import tree_view

    if not Path(path).is_file():
        return _fail(f"tree file not found: '{path}'")
    result = validate(path, plugin_paths=args.plugin_path)
    if result.spec is None:
        for diagnostic in result.diagnostics:
            sys.stderr.write(f"{diagnostic}\n")
        return 1
    return tree_view(result.spec)


def _listen(args: argparse.Namespace) -> socket.socket | int:
    """A socket bound to ``--host``/``--port``, or the exit code when it cannot be."""
    try:
        family = socket.getaddrinfo(args.host, args.port, type=socket.SOCK_STREAM)[0][0]
    except OSError as err:
        return _fail(f"cannot listen on {args.host}:{args.port}: {err.strerror or err}")
    listener = socket.socket(family, socket.SOCK_STREAM)
    listener.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    try:
        listener.bind((args.host, args.port))
        listener.listen(128)  # a page opened as soon as the address is printed waits, never
        #                       finds the port closed
    except OSError as err:
        listener.close()
        return _fail(f"cannot listen on {args.host}:{args.port}: {err.strerror or err}")
    return listener


def _serve(session: Session, args: argparse.Namespace, listener: socket.socket,
           editor: TreeEditor | None, feed: LiveFeed | None) -> int:
    import uvicorn

    from sar_framework.studio.server import make_app

    token = new_token()
    port = listener.getsockname()[1]
    shown = "127.0.0.1" if args.host in ("0.0.0.0", "::") else args.host
    url = f"http://{shown}:{port}/?token={token}"
    sys.stdout.write(f"sar-tree studio {args.mode}: serving on http://{args.host}:{port}/\n"
                     f"    open: {url}\n"
                     "    (the token is needed for anything that writes; Ctrl-C stops)\n")
    sys.stdout.flush()
    if args.open:
        webbrowser.open(url)
    app = make_app(session, token, editor, feed.reload if feed else None,
                   feed.ticked_tree if feed else None)
    config = uvicorn.Config(app, log_level="warning",
                            ws_max_size=MESSAGE_MAX_BYTES, lifespan="off")
    server = uvicorn.Server(config)
    with contextlib.suppress(KeyboardInterrupt):
        server.run(sockets=[listener])
    return EXIT_OK
