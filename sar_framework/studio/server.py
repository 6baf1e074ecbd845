"""The studio's web server: the page, its assets, and one websocket per browser tab.

Starlette (ASGI routing, static files, websockets) served by uvicorn. The page is our own
small HTML, CSS and JavaScript in ``sar_framework/studio/static`` (no framework and no CDN:
it works on a robot with no network). The websocket ``/ws`` speaks JSON:

- the server sends ``hello`` (mode, tree diagram and facts, map, timeline span and marks;
  replayed, every event too, for the page's event list) on connect and again whenever
  the tree or the map changes, and ``frame`` documents
  (:meth:`~sar_framework.studio.timeline.Timeline.frame`): live, after every change of
  the mission, at most every :data:`PUSH_PERIOD_S` and once the page has drawn the last
  (it says ``{"op": "ack"}``); replayed, in answer to ``seek``;
- the page sends ``{"op": "seek", "t": 12.5}`` (replay), ``{"op": "node", "uid":
  "0.1"}`` (answered by a ``node`` document: facts, status history, last reason) and, in
  the editor, ``{"op": "check", "text": "..."}`` (answered by ``checked``: the
  diagnostics and the redrawn diagram, :mod:`.editor`).
  Anything else is answered by ``{"type": "error"}`` and changes nothing
  (:func:`~sar_framework.studio.safety.parse_message`).

``POST /api/save`` (the editor's file; JSON ``{"text": ...}``) needs the session token in
the ``X-Studio-Token`` header, and so does ``POST /api/reload`` (the same body): the text
saved to the running mission's tree file and swapped in by its runner (:mod:`.reload`).
"""

from __future__ import annotations

import asyncio
import contextlib
import json
from pathlib import Path
from typing import Any

from starlette.applications import Starlette
from starlette.requests import Request
from starlette.responses import FileResponse, JSONResponse, Response
from starlette.routing import Mount, Route, WebSocketRoute
from starlette.staticfiles import StaticFiles
from starlette.websockets import WebSocket, WebSocketDisconnect

from sar_framework.studio.editor import TreeEditor
from sar_framework.studio.reload import AskReload, AskTree, apply_to_mission
from sar_framework.studio.safety import MESSAGE_MAX_BYTES, RefusedError, parse_message, token_ok
from sar_framework.studio.session import LIVE, Session

STATIC = Path(__file__).resolve().parent / "static"
#: Shortest time between two frames pushed to one tab (live), seconds.
PUSH_PERIOD_S = 0.01
#: Longest wait for the page's ``ack`` of a frame before the next is sent anyway, seconds.
ACK_WAIT_S = 1.0
TOKEN_HEADER = "x-studio-token"


def _same_origin(websocket: WebSocket) -> bool:
    """Whether a websocket comes from a page this server served (or from no page at all)."""
    origin = websocket.headers.get("origin")
    if origin is None:
        return True
    host = websocket.headers.get("host", "")
    return origin.split("://", 1)[-1].rstrip("/") == host


class _Tab:
    """One browser tab's websocket: what it was sent and where its scrubber is."""

    def __init__(self, websocket: WebSocket, session: Session,
                 editor: TreeEditor | None) -> None:
        self.websocket = websocket
        self.session = session
        self.editor = editor
        self.t: float | None = None if session.mode == LIVE else session.timeline.start_s
        self._send_lock = asyncio.Lock()
        self.drawn = asyncio.Event()
        self._scene: tuple[int, int, int] = (0, 0, 0)

    async def send(self, document: dict[str, Any]) -> None:
        text = json.dumps(document, separators=(",", ":"), default=str)
        async with self._send_lock:
            await self.websocket.send_text(text)

    async def send_scene_and_frame(self) -> None:
        scene = (id(self.session.tree), id(self.session.world), id(self.session.edit))
        if scene != self._scene:
            self._scene = scene
            await self.send(self.session.hello())
        await self.send(self.session.frame(self.t))

    async def push(self, changed: asyncio.Event) -> None:
        """Live: send the newest frame after every change (coalesced).

        The next frame waits until the page has drawn the last one (its ``ack``, or
        :data:`ACK_WAIT_S` at most): a page slower than the mission gets fewer frames,
        never a queue of old ones.
        """
        while True:
            await changed.wait()
            changed.clear()
            self.drawn.clear()
            await self.send_scene_and_frame()
            with contextlib.suppress(asyncio.TimeoutError):
                await asyncio.wait_for(self.drawn.wait(), ACK_WAIT_S)
            await asyncio.sleep(PUSH_PERIOD_S)

    async def answer(self, text: str | bytes) -> None:
        try:
            message = parse_message(text)
        except RefusedError as err:
            await self.send({"type": "error", "message": str(err)})
            return
        if message["op"] == "ack":
            self.drawn.set()
        elif message["op"] == "seek":
            self.t = float(message["t"])
            await self.send(self.session.frame(self.t))
        elif message["op"] == "node":
            await self.send(self.session.node_detail(message["uid"], self.t))
        elif message["op"] == "check":
            editor = self.editor or self.session.editor
            if editor is None:
                await self.send({"type": "error", "message": "no tree is being edited"})
                return
            try:
                checked = await asyncio.to_thread(editor.check, message["text"])
            except RefusedError as err:
                checked = {"type": "error", "message": str(err)}
            await self.send(checked)
        else:  # hello: everything again
            self._scene = (0, 0, 0)
            await self.send_scene_and_frame()


async def _text_of(request: Request) -> str | Response:
    """The ``text`` of a write request's JSON body, or the answer to a bad body."""
    body = await request.body()
    if len(body) > 2 * MESSAGE_MAX_BYTES:
        return JSONResponse({"error": "too large"}, status_code=413)
    try:
        text = json.loads(body)["text"]
    except (ValueError, KeyError, TypeError):
        text = None
    if not isinstance(text, str):
        return JSONResponse({"error": 'the body is JSON {"text": "..."}'}, status_code=400)
    return text


def make_app(session: Session, token: str, editor: TreeEditor | None = None,
             ask_reload: AskReload | None = None, ask_tree: AskTree | None = None
             ) -> Starlette:
    """The studio's ASGI application for ``session``.

    Args:
        session: What to show.
        token: The session token that write requests must present.
        editor: The tree being edited (``edit`` mode; live, the session's editor of the
            mission's tree file, when it knows it).
        ask_reload: Asks the running mission's runner to reload its tree (live).
        ask_tree: Asks which tree file that runner ticks (live).
    """

    async def page(request: Request) -> Response:
        del request
        return FileResponse(STATIC / "index.html", headers={"cache-control": "no-store"})

    async def hello(request: Request) -> Response:
        del request
        return JSONResponse(session.hello())

    async def frame(request: Request) -> Response:
        raw = request.query_params.get("t")
        try:
            t = float(raw) if raw is not None else None
        except ValueError:
            return JSONResponse({"error": f"t must be a number, got {raw!r}"}, status_code=400)
        return JSONResponse(json.loads(json.dumps(session.frame(t), default=str)))

    async def reload(request: Request) -> Response:
        if not token_ok(request.headers.get(TOKEN_HEADER), token):
            return JSONResponse({"error": "a valid session token is required"},
                                status_code=403)
        text = await _text_of(request)
        if isinstance(text, Response):
            return text
        code, answer = await asyncio.to_thread(apply_to_mission, text,
                                               editor or session.editor, ask_reload,
                                               session.mode == LIVE, ask_tree)
        return JSONResponse(answer, status_code=code)

    async def save(request: Request) -> Response:
        if not token_ok(request.headers.get(TOKEN_HEADER), token):
            return JSONResponse({"error": "a valid session token is required"},
                                status_code=403)
        if editor is None:
            return JSONResponse({"error": "no tree is being edited"}, status_code=404)
        text = await _text_of(request)
        if isinstance(text, Response):
            return text
        try:
            return JSONResponse(await asyncio.to_thread(editor.save, text))
        except RefusedError as err:
            return JSONResponse({"error": str(err)}, status_code=403)

    async def socket(websocket: WebSocket) -> None:
        if not _same_origin(websocket):
            await websocket.close(code=1008)
            return
        await websocket.accept()
        tab = _Tab(websocket, session, editor)
        changed = session.listen(asyncio.get_running_loop())
        pusher = asyncio.create_task(tab.push(changed)) if session.mode == LIVE else None
        try:
            await tab.send_scene_and_frame()
            while True:
                received = await websocket.receive()
                if received["type"] == "websocket.disconnect":
                    break
                await tab.answer(received.get("text") or received.get("bytes") or "")
        except (WebSocketDisconnect, RuntimeError):
            pass  # the tab closed
        finally:
            session.forget(changed)
            if pusher is not None:
                pusher.cancel()
                with contextlib.suppress(asyncio.CancelledError, Exception):
                    await pusher

    return Starlette(routes=[
        Route("/", page),
        Route("/api/hello", hello),
        Route("/api/frame", frame),
        Route("/api/reload", reload, methods=["POST"]),
        Route("/api/save", save, methods=["POST"]),
        WebSocketRoute("/ws", socket),
        Mount("/static", StaticFiles(directory=STATIC), name="static"),
    ])
