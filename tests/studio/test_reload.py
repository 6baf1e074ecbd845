"""``POST /api/reload`` without ROS: the text saved to the mission's tree file, the runner's
answer (swapped or refused) passed back, and what is refused before anything is written.
Also the live session's side: swaps and refusals in the reasons feed and on the timeline,
and the diagram drawn again from the file after a swap."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from sar_framework.events.event import EventKind, MissionEvent
from sar_framework.studio.editor import TreeEditor
from sar_framework.studio.reload import ReloadUnavailableError, same_file
from sar_framework.studio.server import TOKEN_HEADER, make_app
from sar_framework.studio.session import EDIT, LIVE, Session
from sar_framework.studio.timeline import Timeline
from sar_framework.studio.tree_view import file_tree_view

testclient = pytest.importorskip("starlette.testclient", reason="httpx is not installed")
pytestmark = pytest.mark.skipif(shutil.which("dot") is None, reason="Graphviz is not installed")

REPO = Path(__file__).resolve().parents[2]
TREE = REPO / "trees" / "tutorials" / "01_first_tree.yaml"
TOKEN = "t" * 48
WORLD = {"grid": None, "places": [], "base": None}


@pytest.fixture
def tree(tmp_path: Path) -> Path:
    path = tmp_path / "mission.yaml"
    shutil.copy(TREE, path)
    return path


def live_client(tree: Path | None, ask, ticked=None) -> testclient.TestClient:
    session = Session(LIVE, None, WORLD, "live")
    session.editor = TreeEditor(tree, [tree]) if tree is not None else None  # the mission's
    return testclient.TestClient(make_app(session, TOKEN, None, ask, ticked))


def post(client: testclient.TestClient, text: str, token: str = TOKEN):
    return client.post("/api/reload", headers={TOKEN_HEADER: token}, json={"text": text})


def test_the_text_is_saved_then_the_runner_swaps_it(tree: Path) -> None:
    asked: list[str] = []

    def ask() -> tuple[bool, str]:
        asked.append(tree.read_text())  # the runner reads the file as saved
        return True, f"Tree swapped from {tree}: 1 added (Again); 3 kept"

    text = tree.read_text() + "# edited\n"
    with live_client(tree, ask) as client:
        answer = post(client, text)
    assert answer.status_code == 200
    body = answer.json()
    assert body["swapped"] is True and "1 added (Again)" in body["message"]
    assert body["saved"] == str(tree) and body["ok"] and body["diagnostics"] == []
    assert asked == [text]


def test_a_refusal_is_passed_back_with_the_diagnostics(tree: Path) -> None:
    bad = tree.read_text().replace("- AdvanceZone", "- AdvanceZon")
    assert bad != tree.read_text()
    refusal = f"Reload of {tree} refused, the tree goes on: {tree}:9:11: error: unknown plugin"
    with live_client(tree, lambda: (False, refusal)) as client:
        body = post(client, bad).json()
    assert body["swapped"] is False and body["message"] == refusal
    assert not body["ok"] and "AdvanceZon" in body["diagnostics"][0]["text"]


def test_no_runner_no_tree_file_no_token_are_said(tree: Path) -> None:
    before = tree.read_text()

    def unreachable() -> tuple[bool, str]:
        raise ReloadUnavailableError("no mission offers /sar_mission_runner/reload")

    with live_client(tree, unreachable) as client:
        answer = post(client, before + "# x\n")
        assert answer.status_code == 503 and "not applied: no mission offers" in \
            answer.json()["error"]
        assert post(client, "x", token="x" * 48).status_code == 403
        assert client.post("/api/reload", headers={TOKEN_HEADER: TOKEN},
                           content=b"{").status_code == 400
    with live_client(None, unreachable) as client:
        answer = post(client, "x")
        assert answer.status_code == 409 and "--tree FILE" in answer.json()["error"]
    session = Session(EDIT, None, WORLD, "tree.yaml")
    with testclient.TestClient(make_app(session, TOKEN, TreeEditor(tree, [tree]))) as client:
        answer = post(client, "x")
        assert answer.status_code == 409 and "no running mission" in answer.json()["error"]
    assert tree.read_text() == before + "# x\n"  # only the unreachable runner's was saved


def event(seq: int, kind: EventKind, sim_s: float, message: str) -> MissionEvent:
    return MissionEvent(seq=seq, kind=kind, sim_s=sim_s, wall_s=sim_s, message=message)


def test_swaps_and_refusals_are_in_the_feed_and_marked() -> None:
    timeline = Timeline()
    timeline.add_event(event(1, EventKind.RELOAD_REFUSED, 2.0, "Reload refused: bad"))
    timeline.add_event(event(2, EventKind.TREE_SWAPPED, 3.0, "Tree swapped: 1 added"))
    assert [r["kind"] for r in timeline.frame(3.0)["reasons"]] == ["tree_swapped",
                                                                  "reload_refused"]
    assert [(m["t"], m["kind"]) for m in timeline.marks()] == [(2.0, "refused"), (3.0, "swap")]


def status(names: list[str]) -> dict:
    nodes = [{"uid": "0", "name": names[0], "kind": "sequence", "status": "RUNNING",
              "message": "", "visited": True, "depth": 0}]
    nodes += [{"uid": f"0.{i}", "name": name, "kind": "x", "status": "INVALID",
               "message": "", "visited": False, "depth": 1}
              for i, name in enumerate(names[1:])]
    return {"tick": 1, "sim_s": 1.0, "nodes": nodes}


def test_after_a_swap_the_diagram_is_the_new_file_with_its_params(tree: Path) -> None:
    old = file_tree_view(str(tree))
    session = Session(LIVE, old, WORLD, "live")
    session.draw_file = lambda: file_tree_view(str(tree))
    tree.write_text(tree.read_text().replace("- AdvanceZone: {}",
                                             "- AdvanceZone: {}\n"
                                             "      - AdvanceZone: {name: Again}"))
    names = [facts["name"] for facts in old["nodes"].values()]
    session.timeline.add_status(status(names), 0.0)
    session.redraw_from_file()  # the running tree is still the old one: its diagram stays
    assert session.tree is old
    new = status([*names, "Again"])
    assert session.adopt_status_tree(new)  # the swapped tree ticks: the file's drawing
    assert session.tree["source"] == "file" and session.tree is not old
    assert {f["name"] for f in session.tree["nodes"].values()} == {*names, "Again"}


def test_a_file_the_runner_does_not_tick_is_refused_unsaved(tree: Path) -> None:
    before = tree.read_text()
    other = tree.parent / "other.yaml"
    with live_client(tree, lambda: (True, "swapped"), lambda: str(other)) as client:
        answer = post(client, "x")
    assert answer.status_code == 409
    assert answer.json()["error"] == (f"the running mission ticks {other}, not {tree}: "
                                      "nothing saved (give the studio its file with --tree)")
    assert tree.read_text() == before
    with live_client(tree, lambda: (True, "swapped"), lambda: str(tree)) as client:
        assert post(client, before).json()["swapped"]


def test_the_runners_tree_parameter_is_matched_as_it_was_given(tree: Path,
                                                                monkeypatch) -> None:
    monkeypatch.chdir(tree.parent)
    assert same_file(str(tree), tree) and same_file("mission.yaml", tree)
    assert same_file("./mission.yaml", tree)
    assert same_file(f"{tree.parent.name}/mission.yaml", tree)  # started one level up
    assert not same_file("other.yaml", tree) and not same_file("/elsewhere/mission.yaml", tree)
    assert not same_file("../x/mission.yaml", tree)


def test_a_live_studio_learns_the_tree_file_the_runner_names(tree: Path, monkeypatch) -> None:
    from sar_framework.studio.command import learn_tree_file

    monkeypatch.chdir(tree.parent)
    session = Session(LIVE, None, WORLD, "live")
    learn_tree_file(session, [], "missing.yaml")  # not found from here: nothing to edit
    assert session.editor is None and session.edit is None
    session.timeline.add_status(status(["NextZone", "ZonesRemaining?", "AdvanceZone"]), 0.0)
    learn_tree_file(session, [], "mission.yaml")
    assert session.editor.path == tree and session.edit["path"] == "mission.yaml"
    assert session.tree["source"] == "file"  # the running tree, drawn from its file
