"""A live view of a run speaks with the apps of the tree's own ``plugins:``, as a replay does.

The live studio (``studio live --tree``) marks the timeline with the app's event kinds and
``sar-tree watch`` puts the app's words in its header, for an app no package installs: the
inspection patrol's, found through its tree's ``plugins:`` folder.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from sar_framework.app.discovery import installed_apps, view_apps
from sar_framework.events.event import MissionEvent
from sar_framework.studio.command import _session
from sar_framework.watch.view import header

PATROL = Path(__file__).resolve().parents[2] / "examples" / "inspection_patrol" / "patrol.yaml"


def test_the_trees_plugins_app_joins_the_installed_ones() -> None:
    names = [app.name for app in view_apps(PATROL)]
    installed = [app.name for app in installed_apps()]
    assert names == [*installed, "inspection_patrol"]
    assert [app.name for app in view_apps(None)] == installed
    assert [app.name for app in view_apps(PATROL.parent / "missing.yaml")] == installed


def test_watch_says_the_plugins_apps_words() -> None:
    document = {"tree": str(PATROL), "tick": 3, "sim_s": 1.0, "status": "RUNNING",
                "shelves_scanned": 2}
    assert "shelves scanned: 2" in header(document, None).plain
    assert "shelves scanned" not in header({**document, "tree": "gone.yaml"}, None).plain


def test_the_live_studio_marks_the_plugins_apps_events() -> None:
    args = argparse.Namespace(mode="live", tree=str(PATROL), run=None, plugin_path=[],
                              params=None, recording=None, root=[])
    session = _session(args, None)
    assert not isinstance(session, int), session
    session.timeline.add_event(MissionEvent("shelf_scanned", seq=1, sim_s=2.0,
                                            message="shelf A scanned", fields={"shelf": "A"}))
    assert [(m["kind"], m["label"]) for m in session.timeline.marks()] == \
        [("found", "shelf_scanned A")]
