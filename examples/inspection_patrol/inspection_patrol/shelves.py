"""The inspection patrol's plugin: the ScanShelf leaf and the app.

The app gives the leaf its context object and the report its words about shelves; the
tree's ``plugins:`` imports this file by path.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from py_trees.common import Status

from sar_framework.app import App, AppRun
from sar_framework.engine.plugin import Param, leaf
from sar_framework.events.emitter import NO_EVENTS, EventEmitter, events_from
from sar_framework.events.event import MissionEvent
from sar_framework.leaves import Leaf

SHELF_SCANNED = "shelf_scanned"
"""The app's event kind: one shelf scanned (field ``shelf``)."""


class Inspection:
    """What the patrol has scanned so far (the app's context object)."""

    def __init__(self) -> None:
        self.scanned: list[str] = []


@leaf(params=[Param("shelf", str, description="The shelf's name.")],
      context=["inspection"])
class ScanShelf(Leaf):
    """Scan ``shelf``: count it in the inspection and record a ``shelf_scanned`` event.

    Attributes:
        shelf: The shelf's name (declared param).
        inspection: The app's :class:`Inspection` (context object).
    """

    shelf: str
    inspection: Inspection

    def __init__(self, name: str, **declared: Any) -> None:
        super().__init__(name, **declared)
        self._events: EventEmitter = NO_EVENTS

    def setup(self, **kwargs: Any) -> None:
        """Keep the event emitter ``setup(events=...)`` gives."""
        self._events = events_from(kwargs)

    def update(self) -> Status:
        """Scan the shelf; SUCCESS."""
        self.inspection.scanned.append(self.shelf)
        self.feedback_message = f"shelf {self.shelf} scanned"
        self._events.emit(SHELF_SCANNED, source=self, message=self.feedback_message,
                          shelf=self.shelf)
        return Status.SUCCESS


def _start(_node: Any, _source: str, _locations: Mapping[str, Any]) -> AppRun:
    """A fresh inspection for the run."""
    return AppRun(context={"inspection": Inspection()})


def _progress(event: MissionEvent) -> str | None:
    """The console line of a scan."""
    return event.message if event.kind == SHELF_SCANNED else None


def _report(_inputs: Any, events: Sequence[MissionEvent],
            document: dict[str, Any]) -> dict[str, Any]:
    """``mission.json``'s ``shelves_scanned`` (with times) and ``waypoints_visited``."""
    from sar_framework.report import since_start

    origin = document.get("sim_start_s")
    scans = [{"shelf": e.value("shelf"), "sim_s": round(since_start(e.sim_s, origin), 2)}
             for e in events if e.kind == SHELF_SCANNED]
    if not scans:
        return {}
    reached = [g["node"] for g in document.get("goals", []) if g.get("result") == "reached"]
    return {"shelves_scanned": scans, "waypoints_visited": reached}


def _summary(document: Mapping[str, Any]) -> list[str]:
    """The summary's words: shelves scanned and waypoints visited."""
    if "shelves_scanned" not in document:
        return []
    shelves = [s["shelf"] for s in document["shelves_scanned"]]
    return [f"shelves scanned: {len(shelves)} ({', '.join(shelves)})",
            f"waypoints visited: {len(document['waypoints_visited'])}"]


APP = App(name="inspection_patrol", provides=("inspection",), start=_start,
          event_kinds={SHELF_SCANNED: "one shelf scanned"}, progress=_progress,
          report=_report, summary=_summary)
