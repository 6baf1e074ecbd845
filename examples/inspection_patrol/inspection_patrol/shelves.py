"""The inspection patrol's plugin: the ScanShelf leaf and the app.

The app starts its scan server (``scan_server.py`` beside this file, a program of its own)
for a tree that uses it, gives the leaf its context object and the report, the studio and
the console its words about shelves; the tree's ``plugins:`` imports this file by path.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from py_trees.common import Status

from sar_framework.app import App, AppRun
from sar_framework.engine.plugin import Param, leaf
from sar_framework.events.emitter import NO_EVENTS, EventEmitter, events_from
from sar_framework.events.event import MissionEvent
from sar_framework.leaves import ServiceLeaf, service_params
from sar_framework.mission.processes import MissionSettings, Process

SHELF_SCANNED = "shelf_scanned"
"""The app's event kind: one shelf scanned (field ``shelf``)."""


SCANNER = "inspection_patrol.scan_server"
"""The scan server's module (``python -m``), in the package this file is in."""


class Inspection:
    """What the patrol has scanned so far (the app's context object)."""

    def __init__(self) -> None:
        self.scanned: list[str] = []


@leaf(params=[Param("shelf", str, description="The shelf's name."),
              *service_params("scan_shelf", server_timeout_s=5.0, response_timeout_s=5.0)],
      context=["inspection"])
class ScanShelf(ServiceLeaf):
    """Ask the app's scan server to scan ``shelf``; record a ``shelf_scanned`` event.

    The server offers a ``std_srvs/srv/Trigger`` service per shelf (``scan_shelf/A``): the
    request carries no fields, the service's name says which shelf.

    Attributes:
        shelf: The shelf's name (declared param).
        inspection: The app's :class:`Inspection` (context object).
    """

    service_type = "std_srvs/srv/Trigger"
    shelf: str
    inspection: Inspection

    def __init__(self, name: str, **declared: Any) -> None:
        super().__init__(name, **declared)
        self.service_name = f"{self.service_name}/{self.shelf}"  # the shelf's own service
        self._events: EventEmitter = NO_EVENTS

    def setup(self, **kwargs: Any) -> None:
        """Keep the event emitter ``setup(events=...)`` gives, then make the client."""
        self._events = events_from(kwargs)
        super().setup(**kwargs)

    def on_response(self, response: Any) -> Status:
        """SUCCESS and a ``shelf_scanned`` event when the server scanned it."""
        if not response.success:
            return self.fail(response.message)
        self.inspection.scanned.append(self.shelf)
        self._events.emit(SHELF_SCANNED, source=self, message=response.message,
                          shelf=self.shelf)
        return self.succeed(response.message, log=False)


def _processes(settings: MissionSettings) -> list[Process]:
    """The scan server, a program of this package, on the mission's clock."""
    return [Process("scan", "", SCANNER, (), {"use_sim_time": settings.use_sim_time},
                    python_path=(str(Path(__file__).resolve().parents[1]),))]


def _start(_node: Any, _source: str, _locations: Mapping[str, Any]) -> AppRun:
    """A fresh inspection for the run; the status says how many shelves it scanned."""
    inspection = Inspection()
    return AppRun(context={"inspection": inspection},
                  status=lambda: {"shelves_scanned": len(inspection.scanned)})


def _status_text(document: Mapping[str, Any]) -> str:
    """``shelves scanned: 4`` in a status line (the studio's header, ``sar-tree watch``)."""
    count = document.get("shelves_scanned")
    return "" if count is None else f"shelves scanned: {count}"


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
          processes=_processes, event_kinds={SHELF_SCANNED: "one shelf scanned"},
          progress=_progress, report=_report, summary=_summary,
          marks={SHELF_SCANNED: "found"}, status_text=_status_text)
