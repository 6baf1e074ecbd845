"""The studio's server without a browser: page, assets, token, and the websocket's guards."""

from __future__ import annotations

import re
import shutil

import pytest

from sar_framework.studio.safety import MESSAGE_MAX_BYTES
from sar_framework.studio.server import STATIC, TOKEN_HEADER, make_app
from sar_framework.studio.session import REPLAY, Session

testclient = pytest.importorskip("starlette.testclient", reason="httpx is not installed")
pytestmark = pytest.mark.skipif(shutil.which("dot") is None, reason="Graphviz is not installed")

TOKEN = "t" * 48
WORLD = {"grid": {"width": 2, "height": 2, "resolution": 1.0, "origin": [0, 0],
                  "walls": [[0, 0, 1]]}, "places": [], "base": None}


def status(tick: int, sim_s: float, leaf: str) -> dict:
    nodes = [{"uid": "0", "name": "Root", "kind": "sequence", "status": "RUNNING",
              "message": "", "visited": True, "depth": 0},
             {"uid": "0.0", "name": "Leaf", "kind": "Wait", "status": leaf,
              "message": "m", "visited": True, "depth": 1}]
    return {"format": 1, "tree": "demo", "tick": tick, "sim_s": sim_s, "status": "RUNNING",
            "complete": False, "zone": None, "nodes": nodes, "blackboard": {}}


@pytest.fixture
def client() -> testclient.TestClient:
    session = Session(REPLAY, None, WORLD, "demo.mcap")
    session.timeline.add_status(status(1, 1.0, "RUNNING"), 0.0)
    session.timeline.add_status(status(2, 2.0, "FAILURE"), 1.0)
    session.adopt_status_tree(session.timeline.statuses[0])
    with testclient.TestClient(make_app(session, TOKEN)) as client:
        yield client


def test_the_page_and_its_assets_are_served_and_need_no_network(client) -> None:
    page = client.get("/")
    assert page.status_code == 200 and "studio.js" in page.text
    for name in ("studio.js", "events.js", "studio.css"):
        assert client.get(f"/static/{name}").status_code == 200
    for asset in STATIC.iterdir():  # no CDN: nothing is fetched from elsewhere
        assert not re.search(r"(src|href)=\"https?://", asset.read_text()), asset.name
    assert client.get("/static/../server.py").status_code == 404


def test_the_tree_is_drawn_from_the_status_when_no_tree_file_is_given(client) -> None:
    hello = client.get("/api/hello").json()
    assert hello["mode"] == "replay" and hello["tree"]["source"] == "status"
    assert "<title>n0_0</title>" in hello["tree"]["svg"]
    assert hello["timeline"]["start"] == 1.0 and hello["timeline"]["end"] == 2.0


def test_a_replay_hello_lists_every_event_and_a_live_one_does_not() -> None:
    from sar_plugins.sar.events import SarKind

    from sar_framework.events.event import EventKind, MissionEvent
    from sar_framework.studio.session import LIVE

    for mode in (REPLAY, LIVE):
        session = Session(mode, None, WORLD, "demo")
        session.timeline.add_status(status(1, 1.0, "RUNNING"), 0.0)
        session.timeline.add_event(MissionEvent(EventKind.NAVIGATION, seq=1, sim_s=1.5,
                                                node_name="Leaf", node_uid="0.0",
                                                fields={"zone_id": "z"}, message="to z"))
        session.timeline.add_event(MissionEvent(SarKind.DETECTION, seq=2, sim_s=2.0,
                                                fields={"zone_id": "z"}, status="FOUND"))
        session.adopt_status_tree(session.timeline.statuses[0])
        with testclient.TestClient(make_app(session, TOKEN)) as client:
            timeline = client.get("/api/hello").json()["timeline"]
        if mode == LIVE:
            assert "events" not in timeline
            continue
        assert [(e["t"], e["kind"], e["node"], e["fields"], e["message"])
                for e in timeline["events"]] == [(1.5, "navigation", "Leaf", ["z"], "to z"),
                                                 (2.0, "detection", "", ["z"], "")]


def test_a_frame_over_http(client) -> None:
    assert client.get("/api/frame?t=1.5").json()["nodes"]["0.0"][0] == "RUNNING"
    assert client.get("/api/frame").json()["nodes"]["0.0"][0] == "FAILURE"
    assert client.get("/api/frame?t=soon").status_code == 400


def test_what_writes_needs_the_token(client) -> None:
    assert client.post("/api/reload").status_code == 403
    assert client.post("/api/reload", headers={TOKEN_HEADER: "x" * 48}).status_code == 403
    answer = client.post("/api/reload", headers={TOKEN_HEADER: TOKEN}, json={"text": "x"})
    assert answer.status_code == 409 and "no running mission" in answer.json()["error"]


def test_the_websocket_says_hello_and_answers_seeks_and_node_questions(client) -> None:
    with client.websocket_connect("/ws") as ws:
        assert ws.receive_json()["type"] == "hello"
        first = ws.receive_json()
        assert first["type"] == "frame" and first["t"] == 1.0
        ws.send_json({"op": "seek", "t": 2.0})
        assert ws.receive_json()["nodes"]["0.0"][0] == "FAILURE"
        ws.send_json({"op": "node", "uid": "0.0"})
        node = ws.receive_json()
        assert node["facts"]["name"] == "Leaf"
        assert node["history"] == [[1.0, "RUNNING"], [2.0, "FAILURE"]]


def test_malformed_messages_are_answered_and_change_nothing(client) -> None:
    with client.websocket_connect("/ws") as ws:
        ws.receive_json(), ws.receive_json()
        for bad in ("{", "[]", '{"op": "delete", "path": "/"}', '{"op": "seek", "t": "x"}'):
            ws.send_text(bad)
            answer = ws.receive_json()
            assert answer["type"] == "error", bad
        ws.send_bytes(b"\x00\x01binary")
        assert ws.receive_json()["type"] == "error"
        ws.send_json({"op": "seek", "t": 1.0})  # still serving, still at the same data
        assert ws.receive_json()["nodes"]["0.0"][0] == "RUNNING"


def test_an_oversized_message_closes_only_that_socket(client) -> None:
    with client.websocket_connect("/ws") as ws:
        ws.receive_json(), ws.receive_json()
        ws.send_text('{"op": "hello", "x": "' + "x" * MESSAGE_MAX_BYTES + '"}')
        assert ws.receive_json()["type"] == "error"
    assert client.get("/api/frame?t=2").json()["tick"] == 2


def test_a_page_from_another_site_cannot_open_the_websocket(client) -> None:
    from starlette.websockets import WebSocketDisconnect

    with pytest.raises(WebSocketDisconnect), \
            client.websocket_connect("/ws", headers={"origin": "http://evil.example"}) as ws:
        ws.receive_json()
    with client.websocket_connect("/ws", headers={"origin": "http://testserver"}) as ws:
        assert ws.receive_json()["type"] == "hello"


def test_the_static_folder_holds_only_our_own_files() -> None:
    assert sorted(p.name for p in STATIC.iterdir()) == ["editor.js", "events.js", "index.html",
                                                         "studio.css", "studio.js"]
